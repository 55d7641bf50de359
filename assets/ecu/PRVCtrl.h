/*
 * File: PRVCtrl.h
 *
 * Code generated for Simulink model 'PRVCtrl' (SW_REQ_ID_003, task 50 ms).
 */

#ifndef PRVCTRL_H
#define PRVCTRL_H

#include "rtwtypes.h"
#include "flcu_types.h"

#define PRVCTRL_FF_TARGET_POINTS 6U
#define PRVCTRL_FF_MANIFOLD_POINTS 5U

/* Block states (default storage): the delay blocks of figures 89 and 90 */
typedef struct {
  real32_T Integrator_DSTATE; /* I[n-1] */
  real32_T Error_DSTATE;      /* e[n-1] */
  real32_T DError_DSTATE;     /* de[n-1] */
} DW_PRVCtrl_T;

extern DW_PRVCtrl_T PRVCtrl_DW;

/* Exported signals (measurements) */
extern real32_T xsRailPressureErr; /* target - rail [bar] */
extern real32_T xsPidP;            /* [%] */
extern real32_T xsPidI;            /* [%] */
extern real32_T xsPidD;            /* [%] */
extern real32_T xsPidFF;           /* feed-forward from xvPRV_DC_FF [%] */
extern real32_T xsDC;              /* PRV duty cycle [%] */

/* Calibrations */
extern real32_T xsPRV_KP;     /* [%/bar] */
extern real32_T xsPRV_KI;     /* [%/(bar s)] */
extern real32_T xsPRV_KD;     /* [% s/bar] */
extern real32_T xsPRV_I_BAND; /* integrate while |e| <= band [bar] */
extern real32_T xsPRV_DC_MIN; /* [%] */
extern real32_T xsPRV_DC_MAX; /* [%] */
extern real32_T xaPRV_FF_TARGET[PRVCTRL_FF_TARGET_POINTS];     /* [bar] */
extern real32_T xaPRV_FF_MANIFOLD[PRVCTRL_FF_MANIFOLD_POINTS]; /* [bar] */
extern real32_T xvPRV_DC_FF[PRVCTRL_FF_MANIFOLD_POINTS][PRVCTRL_FF_TARGET_POINTS]; /* [%] */

extern void PRVCtrl_initialize(void);
extern void PRVCtrl_step(void);

#endif /* PRVCTRL_H */
