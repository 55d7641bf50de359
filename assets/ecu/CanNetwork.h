/*
 * File: CanNetwork.h
 *
 * CAN network driver services used by the generated CAN callbacks (API_CAN<n>_initCbk).
 * Periods and timeouts in milliseconds, DLC in bytes.
 */

#ifndef CANNETWORK_H
#define CANNETWORK_H

#include "api.h"

extern void CanNetwork_SetTxPeriod(CANTxId mbx, uint16_T periodMs);
extern void CanNetwork_SetTxDlc(CANTxId mbx, uint8_T dlc);
extern void CanNetwork_EnableDisableSendMessages(CANTxId mbx, boolean_T enable);
extern void CanNetwork_SetRxPeriod(CANRxId mbx, uint16_T periodMs);
extern void CanNetwork_SetRxTimeout(CANRxId mbx, uint16_T timeoutMs);
extern void CanNetwork_SetRxDlc(CANRxId mbx, uint8_T dlc);
extern void CanNetwork_EnableDisableReceivedMessages(CANRxId mbx, boolean_T enable);

#endif /* CANNETWORK_H */
