"""The mind inspector: ``rosrun rason mind_inspector`` serves one web page for the whole graph.

``store`` (what is known: agents, their mind history, the robots; no ROS, no HTTP), ``graph``
(the ROS side: presence, topics), ``web`` (the aiohttp server and its pushed events), ``main``
(the node), ``static/`` (the page).
"""
