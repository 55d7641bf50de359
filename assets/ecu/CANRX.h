/*
 * File: CANRX.h
 *
 * Code generated for Simulink model 'CANRX' (SW_REQ_ID_001, task 100 ms) from
 * FLCU_CAN2.dbc by the CANRX_MESSAGE block library (thesis 6.3.3).
 */

#ifndef CANRX_H
#define CANRX_H

#include "rtwtypes.h"
#include "flcu_types.h"

/* _BitStatus bits */
#define CANRX_BIT_DLC 0x01U
#define CANRX_BIT_TIMEOUT 0x02U
#define CANRX_BIT_NEWDATA 0x04U
#define CANRX_BIT_CHID 0x08U
#define CANRX_BIT_SIG_OUT_OF_RANGE 0x10U

/* Exported signals (measurements) */
extern tRxPduInfo CANRX_PCM_TO_FLCU_001_Pdu;
extern tRxPduInfo CANRX_PCM_TO_FLCU_002_Pdu;
extern uint8_T csPCM_TO_FLCU_001_EnableFLCU;
extern real32_T csPCM_TO_FLCU_002_TargetRailPressure; /* [bar] */
extern tCANRxStatus csPCM_TO_FLCU_001_Status;
extern uint8_T csPCM_TO_FLCU_001_BitStatus;
extern tCANRxStatus csPCM_TO_FLCU_002_Status;
extern uint8_T csPCM_TO_FLCU_002_BitStatus;

/* Calibrations: signal fixes (raw values) */
extern uint8_T cfENABLEFLCU_EN;
extern uint8_T cfENABLEFLCU_VALUE;
extern uint8_T cfTARGETRAILPRESSURE_EN;
extern uint16_T cfTARGETRAILPRESSURE_VALUE;

extern void CANRX_initialize(void);
extern void CANRX_step(void);

#endif /* CANRX_H */
