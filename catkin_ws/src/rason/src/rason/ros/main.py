"""Entry points: ``rosrun rason agent NAME FILE.asl`` and ``rosrun rason mas FILE.mas2j``."""

from __future__ import annotations

import argparse
import gc
import os
import sys
from pathlib import Path

from rason.asl import AslSyntaxError, ModuleLoadError, load_agent_source, load_mas2j, load_modules
from rason.ros.perceptions import PerceptionFilter

# rospy reads the node's namespace from sys.argv when it is imported, so it is imported only
# after _namespace() has moved the node into <ns>/jason (see _run).


def _namespace(argv: list[str]) -> tuple[str, list[str]]:
    """The robot namespace the user asked for, and argv with the node moved into <ns>/jason.

    rospy node names cannot contain '/', so the node ``jason/NAME`` is the node ``NAME`` in the
    namespace ``<ns>/jason``; topics are then resolved against ``<ns>`` explicitly.
    """
    ns = os.environ.get("ROS_NAMESPACE", "/")
    rest = []
    for arg in argv:
        if arg.startswith("__ns:="):
            ns = arg.split(":=", 1)[1]
        else:
            rest.append(arg)
    ns = "/" + ns.strip("/")
    jason_ns = ns.rstrip("/") + "/jason"
    os.environ.pop("ROS_NAMESPACE", None)
    return ns, [*rest, f"__ns:={jason_ns}"]


def _run(node_name: str, argv: list[str],
         agents: list[tuple[str, Path, PerceptionFilter | None, dict]], ns: str) -> int:
    sources = []
    for name, path, pfilter, options in agents:
        try:
            sources.append((name, load_agent_source(path), path, pfilter, options))
        except OSError as err:
            print(f"rason: cannot read {path}: {err}", file=sys.stderr)
            return 2
        except AslSyntaxError as err:
            print(str(err), file=sys.stderr)
            return 2
    sys.argv = argv
    import rospy

    from rason.ros.node import AgentNodeParams, RasonNode
    from rosnode_kit.master_watch import watch_master
    from rosnode_kit.params import ParamError, forget, load
    from rosnode_kit.rosout import cache_rosout_setting
    from rosnode_kit.signals import init_node

    init_node(node_name)
    cache_rosout_setting()
    try:
        params = load(AgentNodeParams)
    except ParamError as err:
        print(f"rason: bad parameter: {err} {forget(err)}".rstrip(), file=sys.stderr)
        rospy.signal_shutdown("bad parameter")
        return 2
    try:
        added = load_modules(_module_names(params.internal_actions))
    except ModuleLoadError as err:
        print(f"rason: {err}", file=sys.stderr)
        rospy.signal_shutdown("bad ~internal_actions")
        return 2
    if added:
        rospy.loginfo("internal actions loaded: %s", ", ".join(added))
    try:
        node = RasonNode(params, base_ns=ns)
    except ParamError as err:
        print(f"rason: bad parameter: {err} {forget(err)}".rstrip(), file=sys.stderr)
        rospy.signal_shutdown("bad parameter")
        return 2
    try:
        for name, source, path, pfilter, options in sources:
            node.host(name, source, str(path), pfilter, options)
    except AslSyntaxError as err:
        print(str(err), file=sys.stderr)
        rospy.signal_shutdown("syntax error")
        return 2
    # What is loaded by now (rospy, the parser, the agents' plans) lives as long as the node: a
    # full collection would walk its ~45k objects (tens of ms, during which no message is
    # handled) for nothing. Frozen, the collector only looks at what the node makes from now on.
    gc.freeze()
    node.start()
    rospy.on_shutdown(node.shutdown)
    watch_master(on_registered=[node.on_master_restarted])
    rospy.loginfo("hosting %s in namespace %s", ", ".join(node.agents), ns)
    rospy.spin()
    return 0


def _module_names(value: object) -> list[str]:
    """``~internal_actions`` (a YAML list, or ``"[a.b, c]"``) as module names; like
    ``python -m``, the current directory is searched for them too."""
    if isinstance(value, (list, tuple)):
        names = [str(v).strip() for v in value]
    else:
        names = [v.strip() for v in str(value).strip("[]").split(",")]
    names = [n for n in names if n]
    if names and os.getcwd() not in sys.path:
        sys.path.insert(0, os.getcwd())
    return names


def _user_args(argv: list[str]) -> list[str]:
    """argv without the program name and ROS remappings (``a:=b``), like rospy.myargv."""
    return [a for a in argv[1:] if ":=" not in a]


def _parser(prog: str, description: str) -> argparse.ArgumentParser:
    """The command line's parser; its --help ends with the node's parameter table."""
    epilog = None
    if "-h" in sys.argv[1:] or "--help" in sys.argv[1:]:
        # Only printing: rospy (imported with the node module) may now read sys.argv.
        from rason.ros.node import AgentNodeParams
        from rosnode_kit.params import table_text

        epilog = table_text(AgentNodeParams)
    return argparse.ArgumentParser(prog=prog, description=description, epilog=epilog,
                                   formatter_class=argparse.RawDescriptionHelpFormatter)


def agent_main() -> int:
    """``rosrun rason agent NAME FILE.asl [__ns:=/robot] [_param:=value ...]``."""
    ns, argv = _namespace(sys.argv)
    args = _parser("rosrun rason agent", "Run one Jason agent as the ROS node jason/NAME.")
    args.add_argument("name", help="the agent's name (as the .asl world knows it)")
    args.add_argument("file", type=Path, help="the agent's AgentSpeak source (.asl)")
    opts = args.parse_args(_user_args(argv))
    return _run(opts.name, argv, [(opts.name, opts.file, None, {})], ns)


def mas_main() -> int:
    """``rosrun rason mas FILE.mas2j [__ns:=/robot]``: every agent of the project in one node."""
    ns, argv = _namespace(sys.argv)
    args = _parser("rosrun rason mas", "Host every agent of a .mas2j project in one node.")
    args.add_argument("file", type=Path, help="the Jason project file (.mas2j)")
    opts = args.parse_args(_user_args(argv))
    try:
        project = load_mas2j(opts.file)
    except (OSError, AslSyntaxError) as err:
        print(f"rason: {err}", file=sys.stderr)
        return 2
    except UnicodeDecodeError as err:
        print(f"{opts.file}: not UTF-8 text (byte {err.start}); save the file as UTF-8", file=sys.stderr)
        return 2
    if project.environment:
        print(f"rason: environment {project.environment} not loaded: on ROS the robot is the "
              "agents' environment", file=sys.stderr)
    agents = []
    for spec in project.agents:
        pfilter = None
        functors = spec.options.get("perception_functors")
        sources = spec.options.get("perception_sources")
        if functors or sources:
            pfilter = PerceptionFilter.from_lists(_option_list(functors), _option_list(sources))
        if spec.arch_class:
            print(f"rason: agent {spec.name}: agentArchClass {spec.arch_class} noted; "
                  "rason hosts it with RosAgArch", file=sys.stderr)
        for keyword, name in (("agentClass", spec.agent_class), ("beliefBaseClass", spec.bb_class)):
            if name:
                print(f"rason: agent {spec.name}: {keyword} {name} not loaded on ROS (only by "
                      "python -m rason.asl run)", file=sys.stderr)
        agents.append((spec.name, Path(spec.asl_path), pfilter, spec.options))
    return _run(project.name or opts.file.stem, argv, agents, ns)


def _option_list(value: object) -> list[str]:
    """A .mas2j option value such as ``[robot, battery]`` or ``"robot/4"`` as a list."""
    if value is None:
        return []
    if isinstance(value, (list, tuple)):
        return [str(v).strip().strip('"') for v in value]
    return [v.strip().strip('"') for v in str(value).strip("[]").split(",") if v.strip()]
