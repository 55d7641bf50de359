/*
 * File: ActuatorCommands.c
 *
 * Code generated for Simulink model 'ActuatorCommands' (SW_REQ_ID_007, task 50 ms,
 * figure 97). A valve opens only while its driver reports NO_ERROR; the PRV duty
 * cycle is 0 while the PWM driver reports an error.
 */

#include "ActuatorCommands.h"
#include "api.h"
#include "Utils.h"
#include "TankCtrl.h"
#include "PRVCtrl.h"
#include "FuelLevel.h"

/* Definition for custom storage class: Calibration */
/* #pragma section ".cal_ram" */
CAL_RAM uint16_T xsPRV_PWM_PERIOD = 1000U;
/* #pragma section */

/* Exported signals */
uint8_T xsOTV1Cmd;
uint8_T xsOTV2Cmd;
uint8_T xsLEDCmd;
real32_T xsPRVDutyCmd;

/* Duty cycle [%] to the driver's 0.01 % steps, rounded, saturated to [0, 10000] */
static uint16_T ActuatorCommands_dutySteps(real32_T dutyPercent)
{
  if (!(dutyPercent > 0.0F)) { /* also NaN */
    return 0U;
  }
  if (dutyPercent >= 100.0F) {
    return 10000U;
  }
  return (uint16_T)(dutyPercent * 100.0F + 0.5F);
}

void ActuatorCommands_step(void)
{
  xsOTV1Cmd = (xsOTV1DiagStatus == NO_ERROR) ? xsValve1State : 0U;
  xsOTV2Cmd = (xsOTV2DiagStatus == NO_ERROR) ? xsValve2State : 0U;
  xsLEDCmd = xsLEDEn;
  xsPRVDutyCmd = (xsPRVDiagStatus == NO_ERROR) ? xsDC : 0.0F;

  (void)API_DOUT_setDigOut(DOUT_HS_CH_ID_000, xsOTV1Cmd);
  (void)API_DOUT_setDigOut(DOUT_HS_CH_ID_001, xsOTV2Cmd);
  (void)API_DOUT_setDigOut(DOUT_LS_CH_ID_000, xsLEDCmd);
  API_PWMOUT_setPeriodAndDuty(PWMOUT_LS_CH_ID_000, xsPRV_PWM_PERIOD, ActuatorCommands_dutySteps(xsPRVDutyCmd));
}

void ActuatorCommands_initialize(void)
{
  xsOTV1Cmd = 0U;
  xsOTV2Cmd = 0U;
  xsLEDCmd = 0U;
  xsPRVDutyCmd = 0.0F;
}
