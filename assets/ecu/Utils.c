/*
 * File: Utils.c
 *
 * Code generated for Simulink model 'Utils' (SW_REQ_ID_008, task 50 ms).
 * A sensor is OUT_OF_RANGE while its raw voltage is outside
 * [xsDIAG_VOLT_MIN, xsDIAG_VOLT_MAX]; the manifold sensor is IMPLAUSIBLE while a
 * tank valve is commanded open and the manifold pressure differs from that
 * tank's pressure by more than xsMANIFOLD_TOL. Actuator statuses come from the
 * output drivers. Any error disables the system.
 */

#include "Utils.h"
#include "api.h"
#include "PressSens.h"
#include "ActuatorCommands.h"
#include "CANRX.h"

/* Definition for custom storage class: Calibration */
/* #pragma section ".cal_ram" */
CAL_RAM real32_T xsDIAG_VOLT_MIN = 0.5F;
CAL_RAM real32_T xsDIAG_VOLT_MAX = 4.5F;
CAL_RAM real32_T xsMANIFOLD_TOL = 30.0F;
/* #pragma section */

/* Exported signals */
Std_eDiagStatusT xsTank1PSDiagStatus;
Std_eDiagStatusT xsTank2PSDiagStatus;
Std_eDiagStatusT xsManifoldPSDiagStatus;
Std_eDiagStatusT xsRailPSDiagStatus;
Std_eDiagStatusT xsOTV1DiagStatus;
Std_eDiagStatusT xsOTV2DiagStatus;
Std_eDiagStatusT xsPRVDiagStatus;
Std_eDiagStatusT xsLEDDiagStatus;
boolean_T xsSensorDiag;
boolean_T xsActuatorDiag;
boolean_T xsSystemAbilitation;

static Std_eDiagStatusT Utils_voltStatus(real32_T volt)
{
  return ((volt < xsDIAG_VOLT_MIN) || (volt > xsDIAG_VOLT_MAX)) ? OUT_OF_RANGE : NO_ERROR;
}

static boolean_T Utils_deviates(real32_T a, real32_T b)
{
  real32_T diff = a - b;
  if (diff < 0.0F) {
    diff = -diff;
  }
  return (boolean_T)(diff > xsMANIFOLD_TOL);
}

void Utils_step(void)
{
  /* Sensor diagnostic (figure 100) */
  xsTank1PSDiagStatus = Utils_voltStatus(zsSensVolt[PRESSSENS_TANK1]);
  xsTank2PSDiagStatus = Utils_voltStatus(zsSensVolt[PRESSSENS_TANK2]);
  xsManifoldPSDiagStatus = Utils_voltStatus(zsSensVolt[PRESSSENS_MANIFOLD]);
  xsRailPSDiagStatus = Utils_voltStatus(zsSensVolt[PRESSSENS_RAIL]);
  if ((xsManifoldPSDiagStatus == NO_ERROR) &&
      (((xsOTV1Cmd != 0U) && Utils_deviates(zsManifoldPressure, zsTank1Pressure)) ||
       ((xsOTV2Cmd != 0U) && Utils_deviates(zsManifoldPressure, zsTank2Pressure)))) {
    xsManifoldPSDiagStatus = IMPLAUSIBLE;
  }
  xsSensorDiag = (boolean_T)((xsTank1PSDiagStatus == NO_ERROR) && (xsTank2PSDiagStatus == NO_ERROR) &&
                             (xsManifoldPSDiagStatus == NO_ERROR) && (xsRailPSDiagStatus == NO_ERROR));

  /* Actuator diagnostic (figure 99) */
  xsOTV1DiagStatus = API_DOUT_getDigOutErrorInfo(DOUT_HS_CH_ID_000);
  xsOTV2DiagStatus = API_DOUT_getDigOutErrorInfo(DOUT_HS_CH_ID_001);
  xsPRVDiagStatus = API_PWMOUT_getPwmOutErrorInfo(PWMOUT_LS_CH_ID_000);
  xsLEDDiagStatus = API_DOUT_getDigOutErrorInfo(DOUT_LS_CH_ID_000);
  xsActuatorDiag = (boolean_T)((xsOTV1DiagStatus == NO_ERROR) && (xsOTV2DiagStatus == NO_ERROR) &&
                               (xsPRVDiagStatus == NO_ERROR) && (xsLEDDiagStatus == NO_ERROR));

  /* System enable (figure 98) */
  xsSystemAbilitation = (boolean_T)((csPCM_TO_FLCU_001_EnableFLCU != 0U) && (xsSensorDiag != 0U) &&
                                    (xsActuatorDiag != 0U));
}

void Utils_initialize(void)
{
  xsTank1PSDiagStatus = NO_ERROR;
  xsTank2PSDiagStatus = NO_ERROR;
  xsManifoldPSDiagStatus = NO_ERROR;
  xsRailPSDiagStatus = NO_ERROR;
  xsOTV1DiagStatus = NO_ERROR;
  xsOTV2DiagStatus = NO_ERROR;
  xsPRVDiagStatus = NO_ERROR;
  xsLEDDiagStatus = NO_ERROR;
  xsSensorDiag = FALSE;
  xsActuatorDiag = FALSE;
  xsSystemAbilitation = FALSE;
}
