"""The XCP master: the link and its transports (CAN, CAN FD, UDP, TCP), the commands, DAQ, seed & key."""
