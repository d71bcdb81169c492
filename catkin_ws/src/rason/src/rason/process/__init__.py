"""rason.process: supervises ROS processes (a private roscore, rosrun nodes) on this machine or on
the hosts of a LAN of network namespaces; the demo, the campaign, the tests and the benchmarks
start ROS through it."""
