/*
 * File: api.h
 *
 * BSW API of the HDS9 platform (thesis chapter 4.1) as the FLCU application sees
 * it: I/O channels, CAN PDUs and the OS task entry points. Parameters are passed
 * by value and results returned by value so that every function can become a
 * Simulink C Caller block; parameter names appear here for the block ports.
 */

#ifndef API_H
#define API_H

#include "rtwtypes.h"
#include "flcu_types.h"

/* Analog inputs, 0-5 V (ANIN_CH_ID_023 is the supply voltage) */
typedef enum {
  ANIN_CH_ID_000 = 0, ANIN_CH_ID_001, ANIN_CH_ID_002, ANIN_CH_ID_003,
  ANIN_CH_ID_004, ANIN_CH_ID_005, ANIN_CH_ID_006, ANIN_CH_ID_007,
  ANIN_CH_ID_008, ANIN_CH_ID_009, ANIN_CH_ID_010, ANIN_CH_ID_011,
  ANIN_CH_ID_012, ANIN_CH_ID_013, ANIN_CH_ID_014, ANIN_CH_ID_015,
  ANIN_CH_ID_016, ANIN_CH_ID_017, ANIN_CH_ID_018, ANIN_CH_ID_019,
  ANIN_CH_ID_020, ANIN_CH_ID_021, ANIN_CH_ID_022, ANIN_CH_ID_023,
  ANIN_CH_NUM
} ANIN_Channel;

typedef enum {
  DIN_CH_ID_000 = 0, DIN_CH_ID_001, DIN_CH_ID_002, DIN_CH_ID_003,
  DIN_CH_ID_004, DIN_CH_ID_005, DIN_CH_ID_006, DIN_CH_ID_007,
  DIN_CH_NUM
} DigInPinName;

/* Digital outputs: high side (HS) and low side (LS) drivers */
typedef enum {
  DOUT_HS_CH_ID_000 = 0, DOUT_HS_CH_ID_001, DOUT_HS_CH_ID_002, DOUT_HS_CH_ID_003,
  DOUT_LS_CH_ID_000, DOUT_LS_CH_ID_001, DOUT_LS_CH_ID_002, DOUT_LS_CH_ID_003,
  DOUT_CH_NUM
} DigOutPinName;

typedef enum {
  PWMIN_CH_ID_000 = 0, PWMIN_CH_ID_001,
  PWMIN_CH_NUM
} PWMInPinName;

typedef enum {
  PWMOUT_LS_CH_ID_000 = 0, PWMOUT_LS_CH_ID_001, PWMOUT_LS_CH_ID_002, PWMOUT_LS_CH_ID_003,
  PWMOUT_HS_CH_ID_000, PWMOUT_HS_CH_ID_001,
  PWMOUT_CH_NUM
} PWMOutPinName;

/* CAN mailboxes, numbered per network and role in DBC order (workbench dbc table) */
typedef enum {
  CAN2_MSG_RX_000 = 0, /* PCM_TO_FLCU_001 0x110 */
  CAN2_MSG_RX_001,     /* PCM_TO_FLCU_002 0x220 */
  CAN_RX_MSG_NUM
} CANRxId;

typedef enum {
  CAN2_MSG_TX_000 = 0, /* FLCU_TO_PCM_001 0x167 */
  CAN2_MSG_TX_001,     /* FLCU_TO_PCM_002 0x123 */
  CAN2_MSG_TX_002,     /* FLCU_TO_PCM_003 0x145 */
  CAN_TX_MSG_NUM
} CANTxId;

/* Initial payload of every transmitted PDU until the application writes one */
extern const uint8_T DataInitPduIntel[8];

/* Analog inputs */
extern uint16_T API_ANIN_getRawValue(ANIN_Channel u8ANIN_CH_ID);
extern real32_T API_ANIN_getADC(ANIN_Channel numPin);

/* Digital inputs */
extern uint8_T API_DIN_getDigIn(DigInPinName numPin);
extern void API_DIN_setHwPullUp(DigInPinName u8DIN_PU_CH_ID, uint8_T status);

/* Digital outputs */
extern uint8_T API_DOUT_setDigOut(DigOutPinName numPin, uint8_T value);
extern Std_eDiagStatusT API_DOUT_getDigOutErrorInfo(DigOutPinName numPin);

/* PWM: period in microseconds [100, 62500], duty in 0.01 % [0, 10000] */
extern tPWMInInfo API_PWMIN_getPeriodAndDuty(PWMInPinName u8PWMIN_CH_ID, uint8_T bNegative);
extern void API_PWMOUT_setPeriodAndDuty(PWMOutPinName u8PWMOUT_CH_ID, uint16_T u16Period, uint16_T u16Duty);
extern Std_eDiagStatusT API_PWMOUT_getPwmOutErrorInfo(PWMOutPinName numPin);

/* CAN */
extern tRxPduInfo API_CAN_getRxPduInfo(CANRxId frameID);
extern uint8_T API_CAN_setTxPduInfo(CANTxId frameID, tTxPduInfo data_SwSTXPdu);
extern uint8_T API_CAN_setPduTxEnblDisbl(CANTxId frameID, uint8_T status);
extern tCANTxStatus API_CAN_getPduTxEnblDisblStatus(CANTxId frameID);
extern uint8_T API_CAN_setPduRxEnblDisbl(CANRxId frameID, uint8_T status);
extern uint8_T API_CAN_getPduTxStatus(CANTxId frameID);
extern void API_CAN_setPduInitValues(CANTxId frameID, const uint8_T initData[8]);

/* CAN2 driver configuration, called by the CAN driver at start-up */
extern void API_CAN2_initCbk(void);

/* OS */
extern void API_OS_Init(void);
extern void API_OS_Task4ms(void);
extern void API_OS_Task50ms(void);
extern void API_OS_Task100ms(void);

#endif /* API_H */
