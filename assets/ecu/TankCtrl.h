/*
 * File: TankCtrl.h
 *
 * Code generated for Simulink model 'TankCtrl' (SW_REQ_ID_002, task 50 ms).
 */

#ifndef TANKCTRL_H
#define TANKCTRL_H

#include "rtwtypes.h"
#include "flcu_types.h"

/* Exported signals (measurements) */
extern tTankCtrlState xsTankCtrlState; /* Stateflow chart state: OFF, TANK1_ON, TANK2_ON */
extern uint8_T xsValve1State;          /* 1: open OTV1 */
extern uint8_T xsValve2State;          /* 1: open OTV2 */
extern real32_T xsTankPressDiff;       /* tank1 - tank2 [bar] */

/* Calibrations */
extern real32_T xsSWITCH_TANK_THR; /* [bar] */

extern void TankCtrl_initialize(void);
extern void TankCtrl_step(void);

#endif /* TANKCTRL_H */
