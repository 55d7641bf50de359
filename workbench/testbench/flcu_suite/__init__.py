"""The FLCU's software requirements (thesis chapter 7.3, SW_REQ_ID_001-008) as requirement tests: ``workbench test``."""
