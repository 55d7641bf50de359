/*
 * File: CANRX.c
 *
 * Code generated for Simulink model 'CANRX' (SW_REQ_ID_001, task 100 ms).
 * Per message (figure 59): read the PDU from the driver, decode each signal
 * (little endian, factor/offset), saturate it to its DBC range (a difference
 * raises SignalOutOfRange), apply the fix switch, and compute _Status with the
 * priority ChannelIdErr > TimeOut > DLC > NewData missing > SignalOutOfRange and
 * the _BitStatus word. The driver keeps the payload of the last valid frame, so
 * a timed-out message keeps its last good value.
 */

#include "CANRX.h"
#include "api.h"

/* Definition for custom storage class: Calibration */
/* #pragma section ".cal_ram" */
CAL_RAM uint8_T cfENABLEFLCU_EN = 0U;
CAL_RAM uint8_T cfENABLEFLCU_VALUE = 0U;
CAL_RAM uint8_T cfTARGETRAILPRESSURE_EN = 0U;
CAL_RAM uint16_T cfTARGETRAILPRESSURE_VALUE = 0U;
/* #pragma section */

/* Exported signals */
tRxPduInfo CANRX_PCM_TO_FLCU_001_Pdu;
tRxPduInfo CANRX_PCM_TO_FLCU_002_Pdu;
uint8_T csPCM_TO_FLCU_001_EnableFLCU;
real32_T csPCM_TO_FLCU_002_TargetRailPressure;
tCANRxStatus csPCM_TO_FLCU_001_Status;
uint8_T csPCM_TO_FLCU_001_BitStatus;
tCANRxStatus csPCM_TO_FLCU_002_Status;
uint8_T csPCM_TO_FLCU_002_BitStatus;

/* Error_Analyzer and MSG_STATUS (figures 61 and 62) */
static void CANRX_status(const tRxPduInfo *pdu, boolean_T sigOutOfRange, tCANRxStatus *status, uint8_T *bitStatus)
{
  boolean_T noNewData = (boolean_T)(pdu->NewDataReceived == 0U);
  uint8_T bits = 0U;

  if (pdu->ChannelIdErr != 0U) {
    *status = CAN_RX_CHID_ERR;
  } else if (pdu->TimeOut != 0U) {
    *status = CAN_RX_TIMEOUT_ERR;
  } else if (pdu->DlcError != 0U) {
    *status = CAN_RX_DLC_ERR;
  } else if (noNewData) {
    *status = CAN_RX_NEWDATA_ERR;
  } else if (sigOutOfRange) {
    *status = CAN_RX_SIG_OUT_OF_RANGE;
  } else {
    *status = CAN_RX_OK;
  }

  if (pdu->DlcError != 0U) {
    bits |= CANRX_BIT_DLC;
  }
  if (pdu->TimeOut != 0U) {
    bits |= CANRX_BIT_TIMEOUT;
  }
  if (noNewData) {
    bits |= CANRX_BIT_NEWDATA;
  }
  if (pdu->ChannelIdErr != 0U) {
    bits |= CANRX_BIT_CHID;
  }
  if (sigOutOfRange) {
    bits |= CANRX_BIT_SIG_OUT_OF_RANGE;
  }
  *bitStatus = bits;
}

/* PCM_TO_FLCU_001 (0x110, DLC 1): EnableFLCU 0|1@1+ (1,0) [0|1] */
static void CANRX_PCM_TO_FLCU_001(void)
{
  uint8_T value;

  CANRX_PCM_TO_FLCU_001_Pdu = API_CAN_getRxPduInfo(CAN2_MSG_RX_000);

  /* a 1-bit signal cannot leave its range [0, 1] */
  value = (uint8_T)(CANRX_PCM_TO_FLCU_001_Pdu.Data[0] & 0x01U);
  csPCM_TO_FLCU_001_EnableFLCU = (cfENABLEFLCU_EN == 1U) ? cfENABLEFLCU_VALUE : value;

  CANRX_status(&CANRX_PCM_TO_FLCU_001_Pdu, FALSE, &csPCM_TO_FLCU_001_Status, &csPCM_TO_FLCU_001_BitStatus);
}

/* PCM_TO_FLCU_002 (0x220, DLC 4): TargetRailPressure 0|16@1+ (0.01,0) [0|50] "bar" */
static void CANRX_PCM_TO_FLCU_002(void)
{
  uint16_T raw;
  real32_T value;
  boolean_T outOfRange = FALSE;

  CANRX_PCM_TO_FLCU_002_Pdu = API_CAN_getRxPduInfo(CAN2_MSG_RX_001);

  raw = (uint16_T)((uint16_T)CANRX_PCM_TO_FLCU_002_Pdu.Data[0] | ((uint16_T)CANRX_PCM_TO_FLCU_002_Pdu.Data[1] << 8U));
  value = (real32_T)raw * 0.01F;
  /* the minimum 0 bar is raw 0: an unsigned raw value cannot fall below it */
  if (value > 50.0F) {
    value = 50.0F;
    outOfRange = TRUE;
  }
  csPCM_TO_FLCU_002_TargetRailPressure = (cfTARGETRAILPRESSURE_EN == 1U) ? ((real32_T)cfTARGETRAILPRESSURE_VALUE * 0.01F)
                                                                         : value;

  CANRX_status(&CANRX_PCM_TO_FLCU_002_Pdu, outOfRange, &csPCM_TO_FLCU_002_Status, &csPCM_TO_FLCU_002_BitStatus);
}

void CANRX_step(void)
{
  CANRX_PCM_TO_FLCU_001();
  CANRX_PCM_TO_FLCU_002();
}

void CANRX_initialize(void)
{
  static const tRxPduInfo emptyPdu = { 0U, { 0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U }, FALSE, FALSE, FALSE, FALSE };

  CANRX_PCM_TO_FLCU_001_Pdu = emptyPdu;
  CANRX_PCM_TO_FLCU_002_Pdu = emptyPdu;
  csPCM_TO_FLCU_001_EnableFLCU = 0U;
  csPCM_TO_FLCU_002_TargetRailPressure = 0.0F;
  csPCM_TO_FLCU_001_Status = CAN_RX_OK;
  csPCM_TO_FLCU_001_BitStatus = 0U;
  csPCM_TO_FLCU_002_Status = CAN_RX_OK;
  csPCM_TO_FLCU_002_BitStatus = 0U;
}
