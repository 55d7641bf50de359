/*
 * File: PressSens.h
 *
 * Code generated for Simulink model 'PressSens' (SW_REQ_ID_005, task 4 ms).
 */

#ifndef PRESSSENS_H
#define PRESSSENS_H

#include "rtwtypes.h"
#include "flcu_types.h"

/* Index of each sensor in zsSensVolt */
#define PRESSSENS_TANK1 0U
#define PRESSSENS_TANK2 1U
#define PRESSSENS_MANIFOLD 2U
#define PRESSSENS_RAIL 3U
#define PRESSSENS_NUM 4U

/* Exported signals (measurements) */
extern real32_T zsSensVolt[PRESSSENS_NUM]; /* raw sensor voltage [V]: tank1, tank2, manifold, rail */
extern real32_T zsTank1VoltFilt;           /* EWMA-filtered voltage [V] */
extern real32_T zsTank2VoltFilt;
extern real32_T zsManifoldVoltFilt;
extern real32_T zsRailVoltFilt;
extern real32_T zsRailPressureTmp;         /* test point: rail LUT output before the fix switch [bar] */
extern real32_T zsTank1Pressure;           /* [bar] */
extern real32_T zsTank2Pressure;
extern real32_T zsManifoldPressure;
extern real32_T zsRailPressure;

/* Calibrations (custom storage class Calibration, section .cal_ram) */
extern real32_T zsEWMA_ALPHA;
extern real32_T zsSENS_VOLT_MIN;
extern real32_T zsSENS_VOLT_MAX;
extern zvTankPConv_str zvTankPConv;
extern zvRailPConv_str zvRailPConv;
extern uint8_T zfTANK1PRESSURE_EN;
extern real32_T zfTANK1PRESSURE_VALUE;
extern uint8_T zfTANK2PRESSURE_EN;
extern real32_T zfTANK2PRESSURE_VALUE;
extern uint8_T zfMANIFOLDPRESSURE_EN;
extern real32_T zfMANIFOLDPRESSURE_VALUE;
extern uint8_T zfRAILPRESSURE_EN;
extern real32_T zfRAILPRESSURE_VALUE;

extern void PressSens_initialize(void);
extern void PressSens_step(void);

#endif /* PRESSSENS_H */
