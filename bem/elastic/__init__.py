"""The elastic half-space: its operator and pixel kernel, the FFTs with their threads, plans and
wisdom, the mirror product and the device (CPU or GPU) the fields live on."""
