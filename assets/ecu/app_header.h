/*
 * File: app_header.h
 *
 * Identification of the application image: the EPK (EPROM identifier, also
 * MOD_PAR ADDR_EPK in the A2L), the application header at the start of the
 * APPLICATIVE region, the CALIB trailer and the application-valid key word.
 */

#ifndef APP_HEADER_H
#define APP_HEADER_H

#include "rtwtypes.h"

#ifndef FLCU_EPK
#error "FLCU_EPK (the EPK, hhmmssyyyymmdd) must be defined by the build"
#endif

#define APP_HEADER_MAGIC 0x39534448U /* "HDS9" */
#define APP_HEADER_VERSION 1U
#define CAL_TRAILER_MAGIC 0x544C4143U /* "CALT" */
#define EPK_SIZE 16U                  /* 14 characters, NUL padded */

typedef struct {
  uint32_T Magic;
  uint32_T HeaderVersion;
  char_T Epk[EPK_SIZE];       /* same EPK as at ADDR_EPK: calibration and code belong together */
  char_T Project[16];
  char_T SwVersion[16];
  void (*Entry)(void);        /* called by the boot code once the key is valid */
} tAppHeader;

typedef struct {
  uint32_T Magic;
  uint32_T DataStart;         /* first byte of the calibration image (the EPK) */
  uint32_T DataEnd;           /* end of the .cal_ram load image, exclusive */
  uint32_T ValidKey;          /* CAL_VALID_KEY */
} tCalTrailer;

extern const char_T EPK[EPK_SIZE];
extern const tAppHeader AppHeader;
extern const tCalTrailer CalTrailer;
extern volatile uint32_T AppValidKey;

#endif /* APP_HEADER_H */
