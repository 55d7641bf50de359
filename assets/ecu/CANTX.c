/*
 * File: CANTX.c
 *
 * Code generated for Simulink model 'CANTX' (SW_REQ_ID_004, task 100 ms).
 * Per signal (figure 66): physical value -> raw = round((phys - offset) / factor)
 * saturated to the signal's width -> fix switch (cf<SIGNAL>_EN/_VALUE) -> bits
 * of the payload (little endian). Per message (figure 67): the PDU is handed to
 * the driver only while cs<Message>_En == 1.
 */

#include "CANTX.h"
#include "api.h"
#include "PressSens.h"
#include "FuelLevel.h"
#include "Utils.h"

/* Definition for custom storage class: Calibration */
/* #pragma section ".cal_ram" */
CAL_RAM uint8_T csFLCU_TO_PCM_001_En = 1U;
CAL_RAM uint8_T csFLCU_TO_PCM_002_En = 1U;
CAL_RAM uint8_T csFLCU_TO_PCM_003_En = 1U;
CAL_RAM uint8_T cfFUELLEVELLOW_EN = 0U;
CAL_RAM uint8_T cfFUELLEVELLOW_VALUE = 0U;
CAL_RAM uint8_T cfFUELLEVEL_EN = 0U;
CAL_RAM uint16_T cfFUELLEVEL_VALUE = 0U;
CAL_RAM uint8_T cfRAILPRESSURE_EN = 0U;
CAL_RAM uint16_T cfRAILPRESSURE_VALUE = 0U;
CAL_RAM uint8_T cfTANK1PSDIAGSTATUS_EN = 0U;
CAL_RAM uint8_T cfTANK1PSDIAGSTATUS_VALUE = 0U;
CAL_RAM uint8_T cfTANK2PSDIAGSTATUS_EN = 0U;
CAL_RAM uint8_T cfTANK2PSDIAGSTATUS_VALUE = 0U;
CAL_RAM uint8_T cfMANIFOLDPSDIAGSTATUS_EN = 0U;
CAL_RAM uint8_T cfMANIFOLDPSDIAGSTATUS_VALUE = 0U;
CAL_RAM uint8_T cfRAILPSDIAGNOSTICSTATUS_EN = 0U;
CAL_RAM uint8_T cfRAILPSDIAGNOSTICSTATUS_VALUE = 0U;
CAL_RAM uint8_T cfOTV1DIAGSTATUS_EN = 0U;
CAL_RAM uint8_T cfOTV1DIAGSTATUS_VALUE = 0U;
CAL_RAM uint8_T cfOTV2DIAGSTATUS_EN = 0U;
CAL_RAM uint8_T cfOTV2DIAGSTATUS_VALUE = 0U;
CAL_RAM uint8_T cfPRVDIAGSTATUS_EN = 0U;
CAL_RAM uint8_T cfPRVDIAGSTATUS_VALUE = 0U;
CAL_RAM uint8_T cfLEDDIAGSTATUS_EN = 0U;
CAL_RAM uint8_T cfLEDDIAGSTATUS_VALUE = 0U;
/* #pragma section */

/* Exported signals */
tTxPduInfo CANTX_FLCU_TO_PCM_001_Pdu = { 4U, { 0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U } };
tTxPduInfo CANTX_FLCU_TO_PCM_002_Pdu = { 4U, { 0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U } };
tTxPduInfo CANTX_FLCU_TO_PCM_003_Pdu = { 8U, { 0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U } };

/* raw = round(phys / factor) for an unsigned 16-bit signal with offset 0, saturated to [0, 65535] */
static uint16_T CANTX_rawU16(real32_T phys, real32_T factor)
{
  real32_T raw = phys / factor;
  if (!(raw > 0.0F)) { /* also NaN */
    return 0U;
  }
  if (raw >= 65535.0F) {
    return 65535U;
  }
  return (uint16_T)(raw + 0.5F);
}

static uint8_T CANTX_fixU8(uint8_T raw, uint8_T fixEnable, uint8_T fixValue)
{
  return (fixEnable == 1U) ? fixValue : raw;
}

static uint16_T CANTX_fixU16(uint16_T raw, uint8_T fixEnable, uint16_T fixValue)
{
  return (fixEnable == 1U) ? fixValue : raw;
}

/* FLCU_TO_PCM_001 (0x167, DLC 4): FuelLevelLow 0|1@1+ (1,0), FuelLevel 8|16@1+ (0.01,0) "%" */
static void CANTX_FLCU_TO_PCM_001(void)
{
  uint8_T fuelLevelLow = CANTX_fixU8(xsLEDEn, cfFUELLEVELLOW_EN, cfFUELLEVELLOW_VALUE);
  uint16_T fuelLevel = CANTX_fixU16(CANTX_rawU16(xsFuelLevel, 0.01F), cfFUELLEVEL_EN, cfFUELLEVEL_VALUE);

  CANTX_FLCU_TO_PCM_001_Pdu.Dlc = 4U;
  CANTX_FLCU_TO_PCM_001_Pdu.Data[0] = (uint8_T)(fuelLevelLow & 0x01U);
  CANTX_FLCU_TO_PCM_001_Pdu.Data[1] = (uint8_T)(fuelLevel & 0xFFU);
  CANTX_FLCU_TO_PCM_001_Pdu.Data[2] = (uint8_T)(fuelLevel >> 8U);
  CANTX_FLCU_TO_PCM_001_Pdu.Data[3] = 0U;
  if (csFLCU_TO_PCM_001_En == 1U) {
    (void)API_CAN_setTxPduInfo(CAN2_MSG_TX_000, CANTX_FLCU_TO_PCM_001_Pdu);
  }
}

/* FLCU_TO_PCM_002 (0x123, DLC 4): RailPressure 0|16@1+ (0.01,0) "bar" */
static void CANTX_FLCU_TO_PCM_002(void)
{
  uint16_T railPressure = CANTX_fixU16(CANTX_rawU16(zsRailPressure, 0.01F), cfRAILPRESSURE_EN, cfRAILPRESSURE_VALUE);

  CANTX_FLCU_TO_PCM_002_Pdu.Dlc = 4U;
  CANTX_FLCU_TO_PCM_002_Pdu.Data[0] = (uint8_T)(railPressure & 0xFFU);
  CANTX_FLCU_TO_PCM_002_Pdu.Data[1] = (uint8_T)(railPressure >> 8U);
  CANTX_FLCU_TO_PCM_002_Pdu.Data[2] = 0U;
  CANTX_FLCU_TO_PCM_002_Pdu.Data[3] = 0U;
  if (csFLCU_TO_PCM_002_En == 1U) {
    (void)API_CAN_setTxPduInfo(CAN2_MSG_TX_001, CANTX_FLCU_TO_PCM_002_Pdu);
  }
}

/* FLCU_TO_PCM_003 (0x145, DLC 8): eight 8-bit diagnostic statuses, one per byte */
static void CANTX_FLCU_TO_PCM_003(void)
{
  CANTX_FLCU_TO_PCM_003_Pdu.Dlc = 8U;
  CANTX_FLCU_TO_PCM_003_Pdu.Data[0] = CANTX_fixU8(xsTank1PSDiagStatus, cfTANK1PSDIAGSTATUS_EN, cfTANK1PSDIAGSTATUS_VALUE);
  CANTX_FLCU_TO_PCM_003_Pdu.Data[1] = CANTX_fixU8(xsTank2PSDiagStatus, cfTANK2PSDIAGSTATUS_EN, cfTANK2PSDIAGSTATUS_VALUE);
  CANTX_FLCU_TO_PCM_003_Pdu.Data[2] =
      CANTX_fixU8(xsManifoldPSDiagStatus, cfMANIFOLDPSDIAGSTATUS_EN, cfMANIFOLDPSDIAGSTATUS_VALUE);
  CANTX_FLCU_TO_PCM_003_Pdu.Data[3] =
      CANTX_fixU8(xsRailPSDiagStatus, cfRAILPSDIAGNOSTICSTATUS_EN, cfRAILPSDIAGNOSTICSTATUS_VALUE);
  CANTX_FLCU_TO_PCM_003_Pdu.Data[4] = CANTX_fixU8(xsOTV1DiagStatus, cfOTV1DIAGSTATUS_EN, cfOTV1DIAGSTATUS_VALUE);
  CANTX_FLCU_TO_PCM_003_Pdu.Data[5] = CANTX_fixU8(xsOTV2DiagStatus, cfOTV2DIAGSTATUS_EN, cfOTV2DIAGSTATUS_VALUE);
  CANTX_FLCU_TO_PCM_003_Pdu.Data[6] = CANTX_fixU8(xsPRVDiagStatus, cfPRVDIAGSTATUS_EN, cfPRVDIAGSTATUS_VALUE);
  CANTX_FLCU_TO_PCM_003_Pdu.Data[7] = CANTX_fixU8(xsLEDDiagStatus, cfLEDDIAGSTATUS_EN, cfLEDDIAGSTATUS_VALUE);
  if (csFLCU_TO_PCM_003_En == 1U) {
    (void)API_CAN_setTxPduInfo(CAN2_MSG_TX_002, CANTX_FLCU_TO_PCM_003_Pdu);
  }
}

void CANTX_step(void)
{
  CANTX_FLCU_TO_PCM_001();
  CANTX_FLCU_TO_PCM_002();
  CANTX_FLCU_TO_PCM_003();
}

void CANTX_initialize(void)
{
  uint32_T i;

  for (i = 0U; i < 8U; i++) {
    CANTX_FLCU_TO_PCM_001_Pdu.Data[i] = 0U;
    CANTX_FLCU_TO_PCM_002_Pdu.Data[i] = 0U;
    CANTX_FLCU_TO_PCM_003_Pdu.Data[i] = 0U;
  }
  CANTX_FLCU_TO_PCM_001_Pdu.Dlc = 4U;
  CANTX_FLCU_TO_PCM_002_Pdu.Dlc = 4U;
  CANTX_FLCU_TO_PCM_003_Pdu.Dlc = 8U;
}
