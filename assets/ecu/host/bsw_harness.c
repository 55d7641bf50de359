/*
 * File: bsw_harness.c
 *
 * Host test harness of the FLCU application (see bsw_harness.h). The services
 * behave as the simulated ECU's: reading an RX PDU clears NewDataReceived, the
 * PWM duty is in 0.01 % steps, the error infos are what the test set.
 */

#include "bsw_harness.h"

static real32_T Harness_Adc[ANIN_CH_NUM];
static uint8_T Harness_Dout[DOUT_CH_NUM];
static uint8_T Harness_DoutError[DOUT_CH_NUM];
static uint16_T Harness_PwmPeriod[PWMOUT_CH_NUM];
static uint16_T Harness_PwmDuty[PWMOUT_CH_NUM];
static uint8_T Harness_PwmError[PWMOUT_CH_NUM];
static tRxPduInfo Harness_RxPdu[CAN_RX_MSG_NUM];
static tTxPduInfo Harness_TxPdu[CAN_TX_MSG_NUM];
static uint32_T Harness_TxCount[CAN_TX_MSG_NUM];

static void Harness_copy(uint8_T *dst, const uint8_T *src, uint32_T size)
{
  uint32_T i;
  for (i = 0U; i < size; i++) {
    dst[i] = src[i];
  }
}

void Harness_reset(void)
{
  static const uint8_T zeros[sizeof(tRxPduInfo)] = { 0U };
  uint32_T i;

  for (i = 0U; i < ANIN_CH_NUM; i++) {
    Harness_Adc[i] = 0.0F;
  }
  for (i = 0U; i < DOUT_CH_NUM; i++) {
    Harness_Dout[i] = 0U;
    Harness_DoutError[i] = NO_ERROR;
  }
  for (i = 0U; i < PWMOUT_CH_NUM; i++) {
    Harness_PwmPeriod[i] = 0U;
    Harness_PwmDuty[i] = 0U;
    Harness_PwmError[i] = NO_ERROR;
  }
  for (i = 0U; i < CAN_RX_MSG_NUM; i++) {
    Harness_copy((uint8_T *)&Harness_RxPdu[i], zeros, sizeof(tRxPduInfo));
  }
  for (i = 0U; i < CAN_TX_MSG_NUM; i++) {
    Harness_copy((uint8_T *)&Harness_TxPdu[i], zeros, sizeof(tTxPduInfo));
    Harness_TxCount[i] = 0U;
  }
}

void Harness_setAdc(uint32_T channel, real32_T volt)
{
  if (channel < ANIN_CH_NUM) {
    Harness_Adc[channel] = volt;
  }
}

void Harness_setDoutError(uint32_T channel, uint8_T status)
{
  if (channel < DOUT_CH_NUM) {
    Harness_DoutError[channel] = status;
  }
}

void Harness_setPwmOutError(uint32_T channel, uint8_T status)
{
  if (channel < PWMOUT_CH_NUM) {
    Harness_PwmError[channel] = status;
  }
}

void Harness_setRxPdu(uint32_T mbx, const uint8_T pdu[13])
{
  if (mbx < CAN_RX_MSG_NUM) {
    Harness_copy((uint8_T *)&Harness_RxPdu[mbx], pdu, sizeof(tRxPduInfo));
  }
}

uint8_T Harness_getDout(uint32_T channel)
{
  return (channel < DOUT_CH_NUM) ? Harness_Dout[channel] : 0U;
}

uint16_T Harness_getPwmPeriod(uint32_T channel)
{
  return (channel < PWMOUT_CH_NUM) ? Harness_PwmPeriod[channel] : 0U;
}

uint16_T Harness_getPwmDuty(uint32_T channel)
{
  return (channel < PWMOUT_CH_NUM) ? Harness_PwmDuty[channel] : 0U;
}

uint32_T Harness_getTxCount(uint32_T mbx)
{
  return (mbx < CAN_TX_MSG_NUM) ? Harness_TxCount[mbx] : 0U;
}

void Harness_getTxPdu(uint32_T mbx, uint8_T pdu[9])
{
  if (mbx < CAN_TX_MSG_NUM) {
    Harness_copy(pdu, (const uint8_T *)&Harness_TxPdu[mbx], sizeof(tTxPduInfo));
  }
}

/* ------------------------------------------------ BSW services (api.h) */

real32_T API_ANIN_getADC(ANIN_Channel numPin)
{
  return (numPin < ANIN_CH_NUM) ? Harness_Adc[numPin] : 0.0F;
}

uint8_T API_DOUT_setDigOut(DigOutPinName numPin, uint8_T value)
{
  if (numPin >= DOUT_CH_NUM) {
    return 1U;
  }
  Harness_Dout[numPin] = value;
  return 0U;
}

Std_eDiagStatusT API_DOUT_getDigOutErrorInfo(DigOutPinName numPin)
{
  return (numPin < DOUT_CH_NUM) ? Harness_DoutError[numPin] : OUT_OF_RANGE;
}

void API_PWMOUT_setPeriodAndDuty(PWMOutPinName u8PWMOUT_CH_ID, uint16_T u16Period, uint16_T u16Duty)
{
  if (u8PWMOUT_CH_ID < PWMOUT_CH_NUM) {
    Harness_PwmPeriod[u8PWMOUT_CH_ID] = u16Period;
    Harness_PwmDuty[u8PWMOUT_CH_ID] = u16Duty;
  }
}

Std_eDiagStatusT API_PWMOUT_getPwmOutErrorInfo(PWMOutPinName numPin)
{
  return (numPin < PWMOUT_CH_NUM) ? Harness_PwmError[numPin] : OUT_OF_RANGE;
}

tRxPduInfo API_CAN_getRxPduInfo(CANRxId frameID)
{
  tRxPduInfo pdu = { 0U, { 0U, 0U, 0U, 0U, 0U, 0U, 0U, 0U }, FALSE, FALSE, FALSE, TRUE };
  if (frameID < CAN_RX_MSG_NUM) {
    pdu = Harness_RxPdu[frameID];
    Harness_RxPdu[frameID].NewDataReceived = FALSE;
  }
  return pdu;
}

uint8_T API_CAN_setTxPduInfo(CANTxId frameID, tTxPduInfo data_SwSTXPdu)
{
  if (frameID >= CAN_TX_MSG_NUM) {
    return 1U;
  }
  Harness_TxPdu[frameID] = data_SwSTXPdu;
  Harness_TxCount[frameID]++;
  return 0U;
}

void API_CAN_setPduInitValues(CANTxId frameID, const uint8_T initData[8])
{
  if (frameID < CAN_TX_MSG_NUM) {
    Harness_copy(Harness_TxPdu[frameID].Data, initData, 8U);
  }
}
