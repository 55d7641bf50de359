/*
 * File: PressSens.c
 *
 * Code generated for Simulink model 'PressSens' (SW_REQ_ID_005, task 4 ms).
 * Per sensor: volt -> EWMA filter -> saturation [zsSENS_VOLT_MIN, zsSENS_VOLT_MAX]
 * -> LUT -> pressure [bar] -> fix switch.
 */

#include "PressSens.h"
#include "api.h"
#include "rt_lookup.h"

/* Definition for custom storage class: Calibration */
/* #pragma section ".cal_ram" */
CAL_RAM real32_T zsEWMA_ALPHA = 0.2F;
CAL_RAM real32_T zsSENS_VOLT_MIN = 0.5F;
CAL_RAM real32_T zsSENS_VOLT_MAX = 4.5F;

/* 0.5-4.5 V -> 0-800 bar (tank 1, tank 2, manifold) */
CAL_RAM zvTankPConv_str zvTankPConv = {
  { 0.5F, 1.0F, 1.5F, 2.0F, 2.5F, 3.0F, 3.5F, 4.0F, 4.5F },
  { 0.0F, 100.0F, 200.0F, 300.0F, 400.0F, 500.0F, 600.0F, 700.0F, 800.0F }
};

/* 0.5-4.5 V -> 0-50 bar (rail) */
CAL_RAM zvRailPConv_str zvRailPConv = {
  { 0.5F, 1.0F, 1.5F, 2.0F, 2.5F, 3.0F, 3.5F, 4.0F, 4.5F },
  { 0.0F, 6.25F, 12.5F, 18.75F, 25.0F, 31.25F, 37.5F, 43.75F, 50.0F }
};

CAL_RAM uint8_T zfTANK1PRESSURE_EN = 0U;
CAL_RAM real32_T zfTANK1PRESSURE_VALUE = 0.0F;
CAL_RAM uint8_T zfTANK2PRESSURE_EN = 0U;
CAL_RAM real32_T zfTANK2PRESSURE_VALUE = 0.0F;
CAL_RAM uint8_T zfMANIFOLDPRESSURE_EN = 0U;
CAL_RAM real32_T zfMANIFOLDPRESSURE_VALUE = 0.0F;
CAL_RAM uint8_T zfRAILPRESSURE_EN = 0U;
CAL_RAM real32_T zfRAILPRESSURE_VALUE = 0.0F;
/* #pragma section */

/* Exported signals */
real32_T zsSensVolt[PRESSSENS_NUM];
real32_T zsTank1VoltFilt;
real32_T zsTank2VoltFilt;
real32_T zsManifoldVoltFilt;
real32_T zsRailVoltFilt;
real32_T zsRailPressureTmp;
real32_T zsTank1Pressure;
real32_T zsTank2Pressure;
real32_T zsManifoldPressure;
real32_T zsRailPressure;

/* EWMA: filt[n] = filt[n-1] + alpha * (volt - filt[n-1]); returns the saturated voltage */
static real32_T PressSens_filter(real32_T volt, real32_T *filt)
{
  real32_T sat;

  *filt = *filt + zsEWMA_ALPHA * (volt - *filt);
  sat = *filt;
  if (sat > zsSENS_VOLT_MAX) {
    sat = zsSENS_VOLT_MAX;
  } else if (sat < zsSENS_VOLT_MIN) {
    sat = zsSENS_VOLT_MIN;
  }
  return sat;
}

static real32_T PressSens_fix(real32_T value, uint8_T fixEnable, real32_T fixValue)
{
  return (fixEnable == 1U) ? fixValue : value;
}

void PressSens_step(void)
{
  real32_T sat;

  zsSensVolt[PRESSSENS_TANK1] = API_ANIN_getADC(ANIN_CH_ID_000);
  zsSensVolt[PRESSSENS_TANK2] = API_ANIN_getADC(ANIN_CH_ID_001);
  zsSensVolt[PRESSSENS_MANIFOLD] = API_ANIN_getADC(ANIN_CH_ID_002);
  zsSensVolt[PRESSSENS_RAIL] = API_ANIN_getADC(ANIN_CH_ID_003);

  sat = PressSens_filter(zsSensVolt[PRESSSENS_TANK1], &zsTank1VoltFilt);
  zsTank1Pressure = PressSens_fix(look1_iflf_binlc(sat, zvTankPConv.BP1, zvTankPConv.Table, PRESSSENS_LUT_POINTS - 1U),
                                  zfTANK1PRESSURE_EN, zfTANK1PRESSURE_VALUE);

  sat = PressSens_filter(zsSensVolt[PRESSSENS_TANK2], &zsTank2VoltFilt);
  zsTank2Pressure = PressSens_fix(look1_iflf_binlc(sat, zvTankPConv.BP1, zvTankPConv.Table, PRESSSENS_LUT_POINTS - 1U),
                                  zfTANK2PRESSURE_EN, zfTANK2PRESSURE_VALUE);

  sat = PressSens_filter(zsSensVolt[PRESSSENS_MANIFOLD], &zsManifoldVoltFilt);
  zsManifoldPressure = PressSens_fix(look1_iflf_binlc(sat, zvTankPConv.BP1, zvTankPConv.Table, PRESSSENS_LUT_POINTS - 1U),
                                     zfMANIFOLDPRESSURE_EN, zfMANIFOLDPRESSURE_VALUE);

  sat = PressSens_filter(zsSensVolt[PRESSSENS_RAIL], &zsRailVoltFilt);
  zsRailPressureTmp = look1_iflf_binlc(sat, zvRailPConv.BP1, zvRailPConv.Table, PRESSSENS_LUT_POINTS - 1U);
  zsRailPressure = PressSens_fix(zsRailPressureTmp, zfRAILPRESSURE_EN, zfRAILPRESSURE_VALUE);
}

void PressSens_initialize(void)
{
  uint32_T i;

  for (i = 0U; i < PRESSSENS_NUM; i++) {
    zsSensVolt[i] = 0.0F;
  }
  zsTank1VoltFilt = 0.0F;
  zsTank2VoltFilt = 0.0F;
  zsManifoldVoltFilt = 0.0F;
  zsRailVoltFilt = 0.0F;
  zsRailPressureTmp = 0.0F;
  zsTank1Pressure = 0.0F;
  zsTank2Pressure = 0.0F;
  zsManifoldPressure = 0.0F;
  zsRailPressure = 0.0F;
}
