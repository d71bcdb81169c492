"""Log lines without a call to the master each.

rospy copies every log line to ``/rosout`` and, for each one, reads the parameter
``/rosout_disable_topics_generation`` through its parameter cache. The cache keeps no missing
key, so while that parameter is unset (the usual case) every ``rospy.loginfo`` costs an
XML-RPC call to the master: in a fleet whose decomposers log each action, a steady load on the
master and a few milliseconds of CPU per line in the node. :func:`cache_rosout_setting`
subscribes to the parameter once and, when it is unset, caches its default (``False``: topics
are listed, as rospy does); a later change on the master still reaches the node.
"""

from __future__ import annotations

import rospy
import rospy.impl.paramserver

#: the parameter rospy's /rosout handler reads with every log line
ROSOUT_TOPICS_PARAM = "/rosout_disable_topics_generation"


def cache_rosout_setting() -> bool:
    """Call after ``rospy.init_node``; True when the parameter's value is now cached."""
    try:
        rospy.get_param_cached(ROSOUT_TOPICS_PARAM, False)     # subscribes on the master
    except (OSError, rospy.ROSException):
        return False                                           # rospy asks again next time
    cache = rospy.impl.paramserver.get_param_server_cache()
    try:
        cache.get(ROSOUT_TOPICS_PARAM)
    except KeyError:                                           # unset: rospy's default
        cache.set(ROSOUT_TOPICS_PARAM, False)
    return True
