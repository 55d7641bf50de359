/*
 * File: FuelLevel.c
 *
 * Code generated for Simulink model 'FuelLevel' (SW_REQ_ID_006, task 50 ms).
 * Low-fuel LED when both tank pressures are below xsEMPTY_TANK_THR; fuel level
 * = (tank1 + tank2) / (2 * xsFULL_TANK_PRESS) * 100 %, saturated to [0, 100].
 */

#include "FuelLevel.h"
#include "PressSens.h"

/* Definition for custom storage class: Calibration */
/* #pragma section ".cal_ram" */
CAL_RAM real32_T xsEMPTY_TANK_THR = 5.0F;
CAL_RAM real32_T xsFULL_TANK_PRESS = 700.0F;
/* #pragma section */

/* Exported signals */
boolean_T xsLEDEn;
real32_T xsFuelLevel;

void FuelLevel_step(void)
{
  real32_T level;

  xsLEDEn = (boolean_T)((zsTank1Pressure < xsEMPTY_TANK_THR) && (zsTank2Pressure < xsEMPTY_TANK_THR));

  level = ((zsTank1Pressure + zsTank2Pressure) / (2.0F * xsFULL_TANK_PRESS)) * 100.0F;
  if (level > 100.0F) {
    level = 100.0F;
  } else if (level < 0.0F) {
    level = 0.0F;
  }
  xsFuelLevel = level;
}

void FuelLevel_initialize(void)
{
  xsLEDEn = FALSE;
  xsFuelLevel = 0.0F;
}
