/*
 * File: CanNetwork.c
 *
 * CAN network driver configuration tables. On the HDS9 the driver programs the
 * FlexCAN mailboxes from these tables; in the demo image they only hold the
 * configuration written by API_CAN2_initCbk (the simulated ECU configures its
 * CAN2 driver from the DBC instead).
 */

#include "CanNetwork.h"

static uint16_T CanNetwork_TxPeriodMs[CAN_TX_MSG_NUM];
static uint8_T CanNetwork_TxDlc[CAN_TX_MSG_NUM];
static boolean_T CanNetwork_TxEnabled[CAN_TX_MSG_NUM];
static uint16_T CanNetwork_RxPeriodMs[CAN_RX_MSG_NUM];
static uint16_T CanNetwork_RxTimeoutMs[CAN_RX_MSG_NUM];
static uint8_T CanNetwork_RxDlc[CAN_RX_MSG_NUM];
static boolean_T CanNetwork_RxEnabled[CAN_RX_MSG_NUM];

void CanNetwork_SetTxPeriod(CANTxId mbx, uint16_T periodMs)
{
  if (mbx < CAN_TX_MSG_NUM) {
    CanNetwork_TxPeriodMs[mbx] = periodMs;
  }
}

void CanNetwork_SetTxDlc(CANTxId mbx, uint8_T dlc)
{
  if (mbx < CAN_TX_MSG_NUM) {
    CanNetwork_TxDlc[mbx] = dlc;
  }
}

void CanNetwork_EnableDisableSendMessages(CANTxId mbx, boolean_T enable)
{
  if (mbx < CAN_TX_MSG_NUM) {
    CanNetwork_TxEnabled[mbx] = enable;
  }
}

void CanNetwork_SetRxPeriod(CANRxId mbx, uint16_T periodMs)
{
  if (mbx < CAN_RX_MSG_NUM) {
    CanNetwork_RxPeriodMs[mbx] = periodMs;
  }
}

void CanNetwork_SetRxTimeout(CANRxId mbx, uint16_T timeoutMs)
{
  if (mbx < CAN_RX_MSG_NUM) {
    CanNetwork_RxTimeoutMs[mbx] = timeoutMs;
  }
}

void CanNetwork_SetRxDlc(CANRxId mbx, uint8_T dlc)
{
  if (mbx < CAN_RX_MSG_NUM) {
    CanNetwork_RxDlc[mbx] = dlc;
  }
}

void CanNetwork_EnableDisableReceivedMessages(CANRxId mbx, boolean_T enable)
{
  if (mbx < CAN_RX_MSG_NUM) {
    CanNetwork_RxEnabled[mbx] = enable;
  }
}
