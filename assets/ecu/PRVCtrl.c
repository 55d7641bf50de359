/*
 * File: PRVCtrl.c
 *
 * Code generated for Simulink model 'PRVCtrl' (SW_REQ_ID_003, task 50 ms,
 * figure 91): discrete PID on e = target - rail pressure plus a feed-forward
 * map over (target, manifold pressure), Ts = 0.05 s.
 *   P  = KP * e
 *   FF = xvPRV_DC_FF(target, manifold)
 *   I  = I[n-1] + KI * e * Ts while |e| <= I_BAND (else I[n-1]),
 *        limited so that FF + I stays in [DC_MIN, DC_MAX]
 *   D  = KD * ((de[n] + de[n-1]) / 2) / Ts,  de[n] = e[n] - e[n-1]
 *   DC = sat(P + I + D + FF, DC_MIN, DC_MAX)
 * While the system is disabled DC = 0 and every delay is reset.
 */

#include "PRVCtrl.h"
#include "PressSens.h"
#include "Utils.h"
#include "CANRX.h"
#include "rt_lookup.h"

#define PRVCTRL_TS 0.05F

/* Definition for custom storage class: Calibration */
/* #pragma section ".cal_ram" */
CAL_RAM real32_T xsPRV_KP = 5.0F;
CAL_RAM real32_T xsPRV_KI = 2.0F;
CAL_RAM real32_T xsPRV_KD = 0.02F;
CAL_RAM real32_T xsPRV_I_BAND = 5.0F;
CAL_RAM real32_T xsPRV_DC_MIN = 0.0F;
CAL_RAM real32_T xsPRV_DC_MAX = 100.0F;
CAL_RAM real32_T xaPRV_FF_TARGET[PRVCTRL_FF_TARGET_POINTS] = { 0.0F, 10.0F, 20.0F, 30.0F, 40.0F, 50.0F };
CAL_RAM real32_T xaPRV_FF_MANIFOLD[PRVCTRL_FF_MANIFOLD_POINTS] = { 50.0F, 100.0F, 200.0F, 400.0F, 700.0F };

/* Duty cycle that holds the rail at the target for a 20 kg/h flow; one row per
 * manifold pressure, one column per target pressure. */
CAL_RAM real32_T xvPRV_DC_FF[PRVCTRL_FF_MANIFOLD_POINTS][PRVCTRL_FF_TARGET_POINTS] = {
  { 0.0F, 100.0F, 100.0F, 100.0F, 100.0F, 100.0F },
  { 0.0F, 100.0F, 100.0F, 100.0F, 100.0F, 100.0F },
  { 0.0F, 70.0F, 70.0F, 70.0F, 70.0F, 70.0F },
  { 0.0F, 35.0F, 35.0F, 35.0F, 35.0F, 35.0F },
  { 0.0F, 20.0F, 20.0F, 20.0F, 20.0F, 20.0F }
};
/* #pragma section */

/* Block states */
DW_PRVCtrl_T PRVCtrl_DW;

/* Exported signals */
real32_T xsRailPressureErr;
real32_T xsPidP;
real32_T xsPidI;
real32_T xsPidD;
real32_T xsPidFF;
real32_T xsDC;

static real32_T PRVCtrl_saturate(real32_T u, real32_T lower, real32_T upper)
{
  if (u > upper) {
    return upper;
  }
  if (u < lower) {
    return lower;
  }
  return u;
}

void PRVCtrl_step(void)
{
  static const uint32_T maxIndex[2] = { PRVCTRL_FF_TARGET_POINTS - 1U, PRVCTRL_FF_MANIFOLD_POINTS - 1U };
  real32_T dError;
  real32_T absError;

  xsRailPressureErr = csPCM_TO_FLCU_002_TargetRailPressure - zsRailPressure;
  if (xsSystemAbilitation == 0U) {
    xsPidP = 0.0F;
    xsPidI = 0.0F;
    xsPidD = 0.0F;
    xsPidFF = 0.0F;
    xsDC = 0.0F;
    PRVCtrl_DW.Integrator_DSTATE = 0.0F;
    PRVCtrl_DW.Error_DSTATE = 0.0F;
    PRVCtrl_DW.DError_DSTATE = 0.0F;
    return;
  }

  xsPidFF = look2_iflf_binlc(csPCM_TO_FLCU_002_TargetRailPressure, zsManifoldPressure, xaPRV_FF_TARGET,
                             xaPRV_FF_MANIFOLD, &xvPRV_DC_FF[0][0], maxIndex, PRVCTRL_FF_TARGET_POINTS);
  xsPidP = xsPRV_KP * xsRailPressureErr;
  /* integrate only near the target: the rise from 0 bar does not wind the integrator up */
  absError = (xsRailPressureErr < 0.0F) ? -xsRailPressureErr : xsRailPressureErr;
  xsPidI = PRVCtrl_DW.Integrator_DSTATE;
  if (absError <= xsPRV_I_BAND) {
    xsPidI += (xsPRV_KI * xsRailPressureErr) * PRVCTRL_TS;
  }
  xsPidI = PRVCtrl_saturate(xsPidI, xsPRV_DC_MIN - xsPidFF, xsPRV_DC_MAX - xsPidFF);
  dError = xsRailPressureErr - PRVCtrl_DW.Error_DSTATE;
  xsPidD = xsPRV_KD * (((dError + PRVCtrl_DW.DError_DSTATE) * 0.5F) / PRVCTRL_TS);
  xsDC = PRVCtrl_saturate(((xsPidP + xsPidI) + xsPidD) + xsPidFF, xsPRV_DC_MIN, xsPRV_DC_MAX);

  PRVCtrl_DW.Integrator_DSTATE = xsPidI;
  PRVCtrl_DW.Error_DSTATE = xsRailPressureErr;
  PRVCtrl_DW.DError_DSTATE = dError;
}

void PRVCtrl_initialize(void)
{
  xsRailPressureErr = 0.0F;
  xsPidP = 0.0F;
  xsPidI = 0.0F;
  xsPidD = 0.0F;
  xsPidFF = 0.0F;
  xsDC = 0.0F;
  PRVCtrl_DW.Integrator_DSTATE = 0.0F;
  PRVCtrl_DW.Error_DSTATE = 0.0F;
  PRVCtrl_DW.DError_DSTATE = 0.0F;
}
