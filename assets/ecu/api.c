/*
 * File: api.c
 *
 * BSW API of the HDS9 platform (thesis chapter 4.1) for the FLCU demo image:
 * the OS task bodies that call the generated models, the CAN2 driver
 * configuration generated from the DBC, and the I/O and CAN services.
 *
 * On the HDS9 the services drive the MPC5777C peripherals; this demo image is
 * built only for its symbols and layout, so they are stubs that keep the last
 * value written. The simulated ECU implements them in Python
 * (workbench/sim/plant.py and the simulator's CAN2 driver). The host test
 * harness (host/bsw_harness.c) replaces them: it compiles this file with
 * FLCU_HOST_HARNESS defined.
 */

#include "api.h"
#include "CanNetwork.h"
#include "PressSens.h"
#include "Utils.h"
#include "FuelLevel.h"
#include "TankCtrl.h"
#include "PRVCtrl.h"
#include "ActuatorCommands.h"
#include "CANRX.h"
#include "CANTX.h"

const uint8_T DataInitPduIntel[8] = { 0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U };

/* ---------------------------------------------------------------- OS tasks */

void API_OS_Init(void)
{
  PressSens_initialize();
  Utils_initialize();
  FuelLevel_initialize();
  TankCtrl_initialize();
  PRVCtrl_initialize();
  ActuatorCommands_initialize();
  CANRX_initialize();
  CANTX_initialize();
}

void API_OS_Task4ms(void)
{
  PressSens_step();
}

void API_OS_Task50ms(void)
{
  Utils_step();
  FuelLevel_step();
  TankCtrl_step();
  PRVCtrl_step();
  ActuatorCommands_step();
}

void API_OS_Task100ms(void)
{
  CANRX_step();
  CANTX_step();
}

/* -------------------------------------------------- CAN2 driver callbacks */

void API_CAN2_initCbk(void)
{
  // DO NOT DELETE THESE MARKERS FOR CALLBACKS GENERATION
  // <initCbk>

  //callbacks automatically generated for FLCU_TO_PCM_001
  API_CAN_setPduInitValues(CAN2_MSG_TX_000, DataInitPduIntel);
  CanNetwork_SetTxPeriod(CAN2_MSG_TX_000, 100);
  CanNetwork_SetTxDlc(CAN2_MSG_TX_000, 4);
  CanNetwork_EnableDisableSendMessages(CAN2_MSG_TX_000, TRUE);

  //callbacks automatically generated for FLCU_TO_PCM_002
  API_CAN_setPduInitValues(CAN2_MSG_TX_001, DataInitPduIntel);
  CanNetwork_SetTxPeriod(CAN2_MSG_TX_001, 100);
  CanNetwork_SetTxDlc(CAN2_MSG_TX_001, 4);
  CanNetwork_EnableDisableSendMessages(CAN2_MSG_TX_001, TRUE);

  //callbacks automatically generated for FLCU_TO_PCM_003
  API_CAN_setPduInitValues(CAN2_MSG_TX_002, DataInitPduIntel);
  CanNetwork_SetTxPeriod(CAN2_MSG_TX_002, 100);
  CanNetwork_SetTxDlc(CAN2_MSG_TX_002, 8);
  CanNetwork_EnableDisableSendMessages(CAN2_MSG_TX_002, TRUE);

  //callbacks automatically generated for PCM_TO_FLCU_001
  CanNetwork_SetRxPeriod(CAN2_MSG_RX_000, 100);
  CanNetwork_SetRxTimeout(CAN2_MSG_RX_000, 300);
  CanNetwork_SetRxDlc(CAN2_MSG_RX_000, 1);
  CanNetwork_EnableDisableReceivedMessages(CAN2_MSG_RX_000, TRUE);

  //callbacks automatically generated for PCM_TO_FLCU_002
  CanNetwork_SetRxPeriod(CAN2_MSG_RX_001, 100);
  CanNetwork_SetRxTimeout(CAN2_MSG_RX_001, 300);
  CanNetwork_SetRxDlc(CAN2_MSG_RX_001, 4);
  CanNetwork_EnableDisableReceivedMessages(CAN2_MSG_RX_001, TRUE);

  // </initCbk>
}

#ifndef FLCU_HOST_HARNESS

/* ------------------------------------------------------ I/O service stubs */

static real32_T API_ANIN_Volt[ANIN_CH_NUM];
static uint8_T API_DOUT_Value[DOUT_CH_NUM];
static uint16_T API_PWMOUT_PeriodUs[PWMOUT_CH_NUM];
static uint16_T API_PWMOUT_Duty[PWMOUT_CH_NUM];
static tRxPduInfo API_CAN_RxPdu[CAN_RX_MSG_NUM];
static tTxPduInfo API_CAN_TxPdu[CAN_TX_MSG_NUM];
static uint8_T API_CAN_TxEnabled[CAN_TX_MSG_NUM];
static uint8_T API_CAN_RxEnabled[CAN_RX_MSG_NUM];

uint16_T API_ANIN_getRawValue(ANIN_Channel u8ANIN_CH_ID)
{
  uint16_T raw = 0U;
  if (u8ANIN_CH_ID < ANIN_CH_NUM) {
    /* full scale 65535 = 5 V */
    raw = (uint16_T)(API_ANIN_Volt[u8ANIN_CH_ID] * (65535.0F / 5.0F));
  }
  return raw;
}

real32_T API_ANIN_getADC(ANIN_Channel numPin)
{
  return (numPin < ANIN_CH_NUM) ? API_ANIN_Volt[numPin] : 0.0F;
}

uint8_T API_DIN_getDigIn(DigInPinName numPin)
{
  (void)numPin;
  return 0U;
}

void API_DIN_setHwPullUp(DigInPinName u8DIN_PU_CH_ID, uint8_T status)
{
  (void)u8DIN_PU_CH_ID;
  (void)status;
}

uint8_T API_DOUT_setDigOut(DigOutPinName numPin, uint8_T value)
{
  if (numPin >= DOUT_CH_NUM) {
    return 1U;
  }
  API_DOUT_Value[numPin] = value;
  return 0U;
}

Std_eDiagStatusT API_DOUT_getDigOutErrorInfo(DigOutPinName numPin)
{
  return (numPin < DOUT_CH_NUM) ? NO_ERROR : OUT_OF_RANGE;
}

tPWMInInfo API_PWMIN_getPeriodAndDuty(PWMInPinName u8PWMIN_CH_ID, uint8_T bNegative)
{
  tPWMInInfo info = { 0U, 0.0F };
  (void)u8PWMIN_CH_ID;
  (void)bNegative;
  return info;
}

void API_PWMOUT_setPeriodAndDuty(PWMOutPinName u8PWMOUT_CH_ID, uint16_T u16Period, uint16_T u16Duty)
{
  if (u8PWMOUT_CH_ID < PWMOUT_CH_NUM) {
    /* the driver saturates the period to [100, 62500] us and the duty to 100 % */
    API_PWMOUT_PeriodUs[u8PWMOUT_CH_ID] = (u16Period < 100U) ? 100U : ((u16Period > 62500U) ? 62500U : u16Period);
    API_PWMOUT_Duty[u8PWMOUT_CH_ID] = (u16Duty > 10000U) ? 10000U : u16Duty;
  }
}

Std_eDiagStatusT API_PWMOUT_getPwmOutErrorInfo(PWMOutPinName numPin)
{
  return (numPin < PWMOUT_CH_NUM) ? NO_ERROR : OUT_OF_RANGE;
}

/* ------------------------------------------------------ CAN service stubs */

tRxPduInfo API_CAN_getRxPduInfo(CANRxId frameID)
{
  tRxPduInfo pdu = { 0U, { 0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U }, FALSE, FALSE, FALSE, TRUE };
  if (frameID < CAN_RX_MSG_NUM) {
    pdu = API_CAN_RxPdu[frameID];
    API_CAN_RxPdu[frameID].NewDataReceived = FALSE;
  }
  return pdu;
}

uint8_T API_CAN_setTxPduInfo(CANTxId frameID, tTxPduInfo data_SwSTXPdu)
{
  if ((frameID >= CAN_TX_MSG_NUM) || (API_CAN_TxEnabled[frameID] == 0U)) {
    return 1U;
  }
  API_CAN_TxPdu[frameID] = data_SwSTXPdu;
  return 0U;
}

uint8_T API_CAN_setPduTxEnblDisbl(CANTxId frameID, uint8_T status)
{
  if (frameID >= CAN_TX_MSG_NUM) {
    return 1U;
  }
  API_CAN_TxEnabled[frameID] = status;
  return 0U;
}

tCANTxStatus API_CAN_getPduTxEnblDisblStatus(CANTxId frameID)
{
  if (frameID >= CAN_TX_MSG_NUM) {
    return CAN_TX_ERROR;
  }
  return (API_CAN_TxEnabled[frameID] != 0U) ? CAN_TX_ENABLED : CAN_TX_DISABLED;
}

uint8_T API_CAN_setPduRxEnblDisbl(CANRxId frameID, uint8_T status)
{
  if (frameID >= CAN_RX_MSG_NUM) {
    return 1U;
  }
  API_CAN_RxEnabled[frameID] = status;
  return 0U;
}

uint8_T API_CAN_getPduTxStatus(CANTxId frameID)
{
  return (frameID < CAN_TX_MSG_NUM) ? 0U : 1U;
}

void API_CAN_setPduInitValues(CANTxId frameID, const uint8_T initData[8])
{
  uint32_T i;
  if (frameID < CAN_TX_MSG_NUM) {
    API_CAN_TxEnabled[frameID] = 1U;
    for (i = 0U; i < 8U; i++) {
      API_CAN_TxPdu[frameID].Data[i] = initData[i];
    }
  }
}

#endif /* FLCU_HOST_HARNESS */
