/*
 * File: flcu_types.h
 *
 * Data types shared by the FLCU models and the BSW API (Simulink data dictionary
 * "FLCU_root.sldd"): enumerations stored as uint8_T, the CAN PDU buses, the
 * lookup-table structures (one struct type per LUT, named <LUT>_str) and the
 * storage class that places calibrations in the CAL RAM.
 */

#ifndef FLCU_TYPES_H
#define FLCU_TYPES_H

#include "rtwtypes.h"

/* Custom storage class "Calibration" (thesis 6.1). Embedded Coder brackets the
 * definitions with
 *     #pragma section ".cal_ram"
 *     ...
 *     #pragma section
 * gcc has no #pragma section, so the same placement is a section attribute.
 * The linker puts .cal_ram in the CAL RAM (VMA) with its initial values in the
 * CAL ROM (LMA); the boot code copies ROM to RAM before the application starts. */
#define CAL_RAM __attribute__((section(".cal_ram")))

/* Enumerated type: tTankCtrlState (storage type uint8_T) */
typedef uint8_T tTankCtrlState;
#define OFF ((tTankCtrlState)0U)
#define TANK1_ON ((tTankCtrlState)1U)
#define TANK2_ON ((tTankCtrlState)2U)

/* Enumerated type: tCANRxStatus (storage type uint8_T) */
typedef uint8_T tCANRxStatus;
#define CAN_RX_OK ((tCANRxStatus)0U)
#define CAN_RX_DLC_ERR ((tCANRxStatus)1U)
#define CAN_RX_TIMEOUT_ERR ((tCANRxStatus)2U)
#define CAN_RX_NEWDATA_ERR ((tCANRxStatus)3U)
#define CAN_RX_CHID_ERR ((tCANRxStatus)4U)
#define CAN_RX_SIG_OUT_OF_RANGE ((tCANRxStatus)5U)

/* Enumerated type: tCANTxStatus (storage type uint8_T) */
typedef uint8_T tCANTxStatus;
#define CAN_TX_DISABLED ((tCANTxStatus)0U)
#define CAN_TX_ENABLED ((tCANTxStatus)1U)
#define CAN_TX_ERROR ((tCANTxStatus)2U)

/* Enumerated type: Std_eDiagStatusT (storage type uint8_T) */
typedef uint8_T Std_eDiagStatusT;
#define NO_ERROR ((Std_eDiagStatusT)0U)
#define SHORT_TO_GND ((Std_eDiagStatusT)1U)
#define SHORT_TO_BAT ((Std_eDiagStatusT)2U)
#define OPEN_LOAD ((Std_eDiagStatusT)3U)
#define OUT_OF_RANGE ((Std_eDiagStatusT)4U)
#define IMPLAUSIBLE ((Std_eDiagStatusT)5U)

/* Bus: tRxPduInfo, a received CAN frame as the CAN driver keeps it (13 bytes) */
typedef struct {
  uint8_T Dlc;               /* DLC of the last frame received with the expected DLC */
  uint8_T Data[8];           /* payload of that frame (kept after a timeout) */
  boolean_T DlcError;        /* the last frame had a DLC other than the configured one */
  boolean_T TimeOut;         /* no valid frame for the configured RX timeout */
  boolean_T NewDataReceived; /* a valid frame arrived since the previous read */
  boolean_T ChannelIdErr;    /* the frame arrived on another channel than configured */
} tRxPduInfo;

/* Bus: tTxPduInfo, a CAN frame to transmit (9 bytes) */
typedef struct {
  uint8_T Dlc;
  uint8_T Data[8];
} tTxPduInfo;

/* Bus: tPWMInInfo, period [us] and duty [%] of a PWM input */
typedef struct {
  uint32_T Period;
  real32_T Duty;
} tPWMInInfo;

/* Lookup table objects ("Map" storage class): breakpoints, then table values.
 * Linear interpolation, clamped at both ends. */
#define PRESSSENS_LUT_POINTS 9U

typedef struct {
  real32_T BP1[PRESSSENS_LUT_POINTS];   /* sensor voltage [V] */
  real32_T Table[PRESSSENS_LUT_POINTS]; /* pressure [bar] */
} zvTankPConv_str;

typedef struct {
  real32_T BP1[PRESSSENS_LUT_POINTS];   /* sensor voltage [V] */
  real32_T Table[PRESSSENS_LUT_POINTS]; /* pressure [bar] */
} zvRailPConv_str;

#endif /* FLCU_TYPES_H */
