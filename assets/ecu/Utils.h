/*
 * File: Utils.h
 *
 * Code generated for Simulink model 'Utils' (SW_REQ_ID_008, task 50 ms):
 * sensor and actuator diagnostics and the FLCU system enable.
 */

#ifndef UTILS_H
#define UTILS_H

#include "rtwtypes.h"
#include "flcu_types.h"

/* Exported signals (measurements) */
extern Std_eDiagStatusT xsTank1PSDiagStatus;
extern Std_eDiagStatusT xsTank2PSDiagStatus;
extern Std_eDiagStatusT xsManifoldPSDiagStatus;
extern Std_eDiagStatusT xsRailPSDiagStatus;
extern Std_eDiagStatusT xsOTV1DiagStatus;
extern Std_eDiagStatusT xsOTV2DiagStatus;
extern Std_eDiagStatusT xsPRVDiagStatus;
extern Std_eDiagStatusT xsLEDDiagStatus;
extern boolean_T xsSensorDiag;        /* 1: every sensor NO_ERROR */
extern boolean_T xsActuatorDiag;      /* 1: every actuator NO_ERROR */
extern boolean_T xsSystemAbilitation; /* EnableFLCU AND xsSensorDiag AND xsActuatorDiag */

/* Calibrations */
extern real32_T xsDIAG_VOLT_MIN;
extern real32_T xsDIAG_VOLT_MAX;
extern real32_T xsMANIFOLD_TOL;

extern void Utils_initialize(void);
extern void Utils_step(void);

#endif /* UTILS_H */
