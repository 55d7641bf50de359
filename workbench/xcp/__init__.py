"""The XCP master: a link over pyxcp's transports, the commands, DAQ, seed & key."""
