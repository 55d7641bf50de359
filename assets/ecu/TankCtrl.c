/*
 * File: TankCtrl.c
 *
 * Code generated for Simulink model 'TankCtrl' (SW_REQ_ID_002, task 50 ms),
 * Stateflow chart of figure 87:
 *   OFF      -> TANK1_ON  system enabled and not low fuel (TANK2_ON if tank 2 is fuller)
 *   TANK1_ON -> TANK2_ON  tank2 - tank1 > xsSWITCH_TANK_THR
 *   TANK2_ON -> TANK1_ON  tank1 - tank2 > xsSWITCH_TANK_THR
 *   any ON   -> OFF       system disabled or low fuel
 */

#include "TankCtrl.h"
#include "PressSens.h"
#include "FuelLevel.h"
#include "Utils.h"

/* Definition for custom storage class: Calibration */
/* #pragma section ".cal_ram" */
CAL_RAM real32_T xsSWITCH_TANK_THR = 20.0F;
/* #pragma section */

/* Exported signals */
tTankCtrlState xsTankCtrlState;
uint8_T xsValve1State;
uint8_T xsValve2State;
real32_T xsTankPressDiff;

void TankCtrl_step(void)
{
  boolean_T mayRun = (boolean_T)((xsSystemAbilitation != 0U) && (xsLEDEn == 0U));

  xsTankPressDiff = zsTank1Pressure - zsTank2Pressure;
  switch (xsTankCtrlState) {
   case OFF:
    if (mayRun) {
      xsTankCtrlState = (zsTank2Pressure > zsTank1Pressure) ? TANK2_ON : TANK1_ON;
    }
    break;

   case TANK1_ON:
    if (!mayRun) {
      xsTankCtrlState = OFF;
    } else if ((zsTank2Pressure - zsTank1Pressure) > xsSWITCH_TANK_THR) {
      xsTankCtrlState = TANK2_ON;
    }
    break;

   case TANK2_ON:
    if (!mayRun) {
      xsTankCtrlState = OFF;
    } else if ((zsTank1Pressure - zsTank2Pressure) > xsSWITCH_TANK_THR) {
      xsTankCtrlState = TANK1_ON;
    }
    break;

   default:
    xsTankCtrlState = OFF;
    break;
  }
  xsValve1State = (uint8_T)(xsTankCtrlState == TANK1_ON);
  xsValve2State = (uint8_T)(xsTankCtrlState == TANK2_ON);
}

void TankCtrl_initialize(void)
{
  xsTankCtrlState = OFF;
  xsValve1State = 0U;
  xsValve2State = 0U;
  xsTankPressDiff = 0.0F;
}
