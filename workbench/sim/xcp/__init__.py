"""The XCP slave of the simulated ECU: protocol names, session and dispatch, CAL/PAG, DAQ, PGM."""
