/*
 * File: ActuatorCommands.h
 *
 * Code generated for Simulink model 'ActuatorCommands' (SW_REQ_ID_007, task 50 ms).
 */

#ifndef ACTUATORCOMMANDS_H
#define ACTUATORCOMMANDS_H

#include "rtwtypes.h"
#include "flcu_types.h"

/* Exported signals (measurements) */
extern uint8_T xsOTV1Cmd;      /* tank 1 valve output (DOUT_HS_CH_ID_000) */
extern uint8_T xsOTV2Cmd;      /* tank 2 valve output (DOUT_HS_CH_ID_001) */
extern uint8_T xsLEDCmd;       /* low-fuel LED output (DOUT_LS_CH_ID_000) */
extern real32_T xsPRVDutyCmd;  /* PRV duty cycle (PWMOUT_LS_CH_ID_000) [%] */

/* Calibrations */
extern uint16_T xsPRV_PWM_PERIOD; /* [us] */

extern void ActuatorCommands_initialize(void);
extern void ActuatorCommands_step(void);

#endif /* ACTUATORCOMMANDS_H */
