"""SW_REQ_ID_001 CANRX: the PCM's messages read every 100 ms, their fix values, saturation and status."""

from __future__ import annotations

from workbench.testbench import equals, needs_simulator, other_than, requirement

from .flcu import CAN_PERIOD_S, RX_LATENCY_S, RX_TIMEOUT_S, TARGET_MAX_BAR, TASK_100MS_S, HOST_SLACK_S, start_pcm

ENABLE, TARGET = "csPCM_TO_FLCU_001_EnableFLCU", "csPCM_TO_FLCU_002_TargetRailPressure"
STATUS_1, STATUS_2, BITS_2 = "csPCM_TO_FLCU_001_Status", "csPCM_TO_FLCU_002_Status", "csPCM_TO_FLCU_002_BitStatus"
RESOLUTION_BAR = 0.01  # TargetRailPressure: 0.01 bar per bit (DBC)


@requirement("SW_REQ_ID_001.1")
def test_enable_is_read_from_frame_0x110(ecu):
    """EnableFLCU arrives in frame 0x110 and is read every 100 ms: the value follows the PCM within a
    frame and a CANRX period, and each CANRX step finds new data (status OK throughout)."""
    assert ecu.can2.message("PCM_TO_FLCU_001").frame_id == 0x110, "the DBC puts PCM_TO_FLCU_001 elsewhere"
    ecu.watch(ENABLE, STATUS_1)
    ecu.send("PCM_TO_FLCU_001", period=CAN_PERIOD_S, EnableFLCU=0)
    ecu.wait_until(ENABLE, 0, timeout=RX_LATENCY_S)  # whatever the ECU last received
    ecu.send("PCM_TO_FLCU_001", EnableFLCU=1)
    ecu.expect_edge(ENABLE, 1, within=RX_LATENCY_S)
    ecu.expect(STATUS_1, "CAN_RX_OK", for_s=0.5)
    ecu.send("PCM_TO_FLCU_001", EnableFLCU=0)
    ecu.expect_edge(ENABLE, 0, within=RX_LATENCY_S)


@requirement("SW_REQ_ID_001.2")
def test_target_rail_pressure_is_read_from_frame_0x220(ecu):
    """TargetRailPressure arrives in frame 0x220 and is read every 100 ms, to its resolution."""
    assert ecu.can2.message("PCM_TO_FLCU_002").frame_id == 0x220, "the DBC puts PCM_TO_FLCU_002 elsewhere"
    ecu.watch(TARGET, STATUS_2)
    ecu.send("PCM_TO_FLCU_002", period=CAN_PERIOD_S, TargetRailPressure=12.5)
    ecu.wait_until(TARGET, equals(12.5, RESOLUTION_BAR), timeout=RX_LATENCY_S)  # whatever the ECU last received
    ecu.send("PCM_TO_FLCU_002", TargetRailPressure=30.0)
    ecu.expect_edge(TARGET, equals(30.0, RESOLUTION_BAR), within=RX_LATENCY_S)
    ecu.send("PCM_TO_FLCU_002", TargetRailPressure=12.5)
    ecu.expect_edge(TARGET, equals(12.5, RESOLUTION_BAR), within=RX_LATENCY_S)
    ecu.expect(STATUS_2, "CAN_RX_OK", for_s=0.3)


@requirement("SW_REQ_ID_001.2")
def test_a_message_that_stops_times_out_after_300_ms_and_keeps_its_value(ecu):
    """A message not received for 300 ms is a timeout (GenMsgTimeoutTime); the last good value is kept.
    The last frame went at most one period before the stop, so no timeout may show before 300 - 100 ms,
    and it must show by 300 ms plus a CANRX period after the stop."""
    ecu.watch(TARGET, STATUS_2)
    ecu.send("PCM_TO_FLCU_002", period=CAN_PERIOD_S, TargetRailPressure=30.0)
    ecu.wait_until(TARGET, equals(30.0, RESOLUTION_BAR), timeout=RX_LATENCY_S)
    ecu.stop("PCM_TO_FLCU_002")
    stopped = ecu.last_stimulus
    ecu.expect(STATUS_2, other_than("CAN_RX_TIMEOUT_ERR"), for_s=RX_TIMEOUT_S - CAN_PERIOD_S - HOST_SLACK_S)
    ecu.expect_edge(STATUS_2, "CAN_RX_TIMEOUT_ERR", within=RX_TIMEOUT_S + TASK_100MS_S + HOST_SLACK_S, after=stopped)
    ecu.expect(TARGET, equals(30.0, RESOLUTION_BAR), for_s=0.3)


@requirement("SW_REQ_ID_001.3")
def test_fix_values_replace_the_received_ones(ecu):
    """While a CAN fix is on, the ECU uses its value instead of the PCM's; released, the PCM's again."""
    ecu.watch(ENABLE, TARGET)
    start_pcm(ecu, enable=0, target_bar=25.0)
    ecu.wait_until(TARGET, equals(25.0, RESOLUTION_BAR), timeout=RX_LATENCY_S)
    ecu.override("cfTARGETRAILPRESSURE", 40.0)
    ecu.expect_edge(TARGET, equals(40.0, RESOLUTION_BAR), within=TASK_100MS_S + HOST_SLACK_S)
    ecu.override("cfENABLEFLCU", "Enabled")
    ecu.expect_edge(ENABLE, 1, within=TASK_100MS_S + HOST_SLACK_S)
    ecu.expect(TARGET, equals(40.0, RESOLUTION_BAR), for_s=0.3)
    ecu.release("cfTARGETRAILPRESSURE")
    ecu.expect_edge(TARGET, equals(25.0, RESOLUTION_BAR), within=TASK_100MS_S + HOST_SLACK_S)
    ecu.release("cfENABLEFLCU")
    ecu.expect_edge(ENABLE, 0, within=TASK_100MS_S + HOST_SLACK_S)


@requirement("SW_REQ_ID_001.4")
def test_a_target_beyond_its_range_is_saturated_and_flagged(ecu):
    """TargetRailPressure above its DBC range (0..50 bar; the 16-bit signal carries up to 655 bar) is read
    as 50 bar and the message status says SIGNAL_OUT_OF_RANGE; back in range, the status is OK again."""
    ecu.watch(TARGET, STATUS_2)
    ecu.send("PCM_TO_FLCU_002", period=CAN_PERIOD_S, TargetRailPressure=25.0)
    ecu.wait_until(STATUS_2, "CAN_RX_OK", timeout=RX_LATENCY_S)
    ecu.send("PCM_TO_FLCU_002", TargetRailPressure=60.0)
    ecu.expect_edge(TARGET, equals(TARGET_MAX_BAR, RESOLUTION_BAR), within=RX_LATENCY_S)
    ecu.expect(STATUS_2, "CAN_RX_SIG_OUT_OF_RANGE", for_s=0.3)
    ecu.send("PCM_TO_FLCU_002", TargetRailPressure=25.0)
    ecu.expect_edge(STATUS_2, "CAN_RX_OK", within=RX_LATENCY_S)


@requirement("SW_REQ_ID_001.4")
@needs_simulator
def test_message_status_priority(ecu):
    """ChannelIdErr > Timeout > DLC > NewData > SignalOutOfRange: each fault added on top of the ones before
    becomes the status, the bit status shows them all; taken away, the one below shows again."""
    ecu.watch(STATUS_2, BITS_2)
    ecu.send("PCM_TO_FLCU_002", period=CAN_PERIOD_S, TargetRailPressure=60.0)
    ecu.wait_until(STATUS_2, "CAN_RX_SIG_OUT_OF_RANGE", timeout=RX_LATENCY_S)
    # frames of 2 bytes instead of 4: not copied (no new data), the old out-of-range value stays
    ecu.send("PCM_TO_FLCU_002", TargetRailPressure=60.0, dlc=2)
    bad_frames = ecu.last_stimulus
    ecu.expect_edge(STATUS_2, "CAN_RX_DLC_ERR", within=RX_LATENCY_S)
    # no good frame for 300 ms (the last one went before the bad ones): the timeout outranks the DLC error
    ecu.expect_edge(STATUS_2, "CAN_RX_TIMEOUT_ERR", within=RX_TIMEOUT_S + TASK_100MS_S + HOST_SLACK_S,
                    after=bad_frames)
    ecu.sim.channel_id_error("PCM_TO_FLCU_002")
    ecu.expect_edge(STATUS_2, "CAN_RX_CHID_ERR", within=TASK_100MS_S + HOST_SLACK_S)
    ecu.expect(BITS_2, 0x1F, for_s=0.2)  # DLC | timeout | no new data | channel id | out of range
    ecu.sim.channel_id_error("PCM_TO_FLCU_002", active=False)
    ecu.expect_edge(STATUS_2, "CAN_RX_TIMEOUT_ERR", within=TASK_100MS_S + HOST_SLACK_S)
    ecu.send("PCM_TO_FLCU_002", TargetRailPressure=60.0)  # good frames again, still out of range
    ecu.expect_edge(STATUS_2, "CAN_RX_SIG_OUT_OF_RANGE", within=RX_LATENCY_S)
    ecu.stop("PCM_TO_FLCU_002")  # no new data in the next CANRX step, before the timeout
    ecu.expect_edge(STATUS_2, "CAN_RX_NEWDATA_ERR", within=RX_LATENCY_S)
