"""kobuki_fault_injector."""
