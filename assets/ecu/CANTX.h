/*
 * File: CANTX.h
 *
 * Code generated for Simulink model 'CANTX' (SW_REQ_ID_004, task 100 ms) from
 * FLCU_CAN2.dbc by the CANTX_MESSAGE block library (thesis 6.3.4).
 */

#ifndef CANTX_H
#define CANTX_H

#include "rtwtypes.h"
#include "flcu_types.h"

/* Exported signals (measurements): the payloads as last encoded */
extern tTxPduInfo CANTX_FLCU_TO_PCM_001_Pdu;
extern tTxPduInfo CANTX_FLCU_TO_PCM_002_Pdu;
extern tTxPduInfo CANTX_FLCU_TO_PCM_003_Pdu;

/* Calibrations: transmission enables */
extern uint8_T csFLCU_TO_PCM_001_En;
extern uint8_T csFLCU_TO_PCM_002_En;
extern uint8_T csFLCU_TO_PCM_003_En;

/* Calibrations: signal fixes (raw values) */
extern uint8_T cfFUELLEVELLOW_EN;
extern uint8_T cfFUELLEVELLOW_VALUE;
extern uint8_T cfFUELLEVEL_EN;
extern uint16_T cfFUELLEVEL_VALUE;
extern uint8_T cfRAILPRESSURE_EN;
extern uint16_T cfRAILPRESSURE_VALUE;
extern uint8_T cfTANK1PSDIAGSTATUS_EN;
extern uint8_T cfTANK1PSDIAGSTATUS_VALUE;
extern uint8_T cfTANK2PSDIAGSTATUS_EN;
extern uint8_T cfTANK2PSDIAGSTATUS_VALUE;
extern uint8_T cfMANIFOLDPSDIAGSTATUS_EN;
extern uint8_T cfMANIFOLDPSDIAGSTATUS_VALUE;
extern uint8_T cfRAILPSDIAGNOSTICSTATUS_EN;
extern uint8_T cfRAILPSDIAGNOSTICSTATUS_VALUE;
extern uint8_T cfOTV1DIAGSTATUS_EN;
extern uint8_T cfOTV1DIAGSTATUS_VALUE;
extern uint8_T cfOTV2DIAGSTATUS_EN;
extern uint8_T cfOTV2DIAGSTATUS_VALUE;
extern uint8_T cfPRVDIAGSTATUS_EN;
extern uint8_T cfPRVDIAGSTATUS_VALUE;
extern uint8_T cfLEDDIAGSTATUS_EN;
extern uint8_T cfLEDDIAGSTATUS_VALUE;

extern void CANTX_initialize(void);
extern void CANTX_step(void);

#endif /* CANTX_H */
