/*
 * File: FuelLevel.h
 *
 * Code generated for Simulink model 'FuelLevel' (SW_REQ_ID_006, task 50 ms).
 */

#ifndef FUELLEVEL_H
#define FUELLEVEL_H

#include "rtwtypes.h"
#include "flcu_types.h"

/* Exported signals (measurements) */
extern boolean_T xsLEDEn;    /* low fuel: both tanks below xsEMPTY_TANK_THR */
extern real32_T xsFuelLevel; /* [%] */

/* Calibrations */
extern real32_T xsEMPTY_TANK_THR;  /* [bar] */
extern real32_T xsFULL_TANK_PRESS; /* [bar] */

extern void FuelLevel_initialize(void);
extern void FuelLevel_step(void);

#endif /* FUELLEVEL_H */
