/*
 * File: bsw_harness.h
 *
 * Host test harness of the FLCU application: replaces the BSW services of
 * api.c (compiled with FLCU_HOST_HARNESS) so a test can set the inputs, read
 * the outputs and run API_OS_Init / API_OS_Task* from Python (ctypes).
 */

#ifndef BSW_HARNESS_H
#define BSW_HARNESS_H

#include "api.h"

/* Inputs */
extern void Harness_reset(void);
extern void Harness_setAdc(uint32_T channel, real32_T volt);
extern void Harness_setDoutError(uint32_T channel, uint8_T status);
extern void Harness_setPwmOutError(uint32_T channel, uint8_T status);
extern void Harness_setRxPdu(uint32_T mbx, const uint8_T pdu[13]); /* the 13 bytes of tRxPduInfo */

/* Outputs */
extern uint8_T Harness_getDout(uint32_T channel);
extern uint16_T Harness_getPwmPeriod(uint32_T channel);
extern uint16_T Harness_getPwmDuty(uint32_T channel);
extern uint32_T Harness_getTxCount(uint32_T mbx);   /* API_CAN_setTxPduInfo calls so far */
extern void Harness_getTxPdu(uint32_T mbx, uint8_T pdu[9]); /* the 9 bytes of the last tTxPduInfo */

#endif /* BSW_HARNESS_H */
