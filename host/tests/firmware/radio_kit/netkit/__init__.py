# A kit library in the style of a robot vendor's (XRPLib's shape, not its code): its
# defaults module builds every default object as it is imported, a web server among them,
# which takes the radio and a socket before the firmware's own code runs.
