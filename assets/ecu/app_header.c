/*
 * File: app_header.c
 *
 * EPK, application header, CALIB trailer and the application-valid key word,
 * each in its own section so the linker script can place it (flcu.ld).
 */

#include "app_header.h"
#include "boot_key.h"
#include "api.h"

/* Linker script symbol: end of the .cal_ram load image in CAL ROM */
extern const char_T __cal_ram_load_end[];

/* ADDR_EPK 0xFC0000: first bytes of the CALIB region, copied to CAL RAM with the calibrations */
__attribute__((section(".epk"))) const char_T EPK[EPK_SIZE] = FLCU_EPK;

__attribute__((section(".app_header"))) const tAppHeader AppHeader = {
  APP_HEADER_MAGIC,
  APP_HEADER_VERSION,
  FLCU_EPK,
  "FLCU",
  "1.0.0",
  &API_OS_Init
};

__attribute__((section(".cal_trailer"))) const tCalTrailer CalTrailer = {
  CAL_TRAILER_MAGIC,
  (uint32_T)EPK,
  (uint32_T)__cal_ram_load_end,
  CAL_VALID_KEY
};

/* Written by the boot code after a verified application flash; NOLOAD */
__attribute__((section(".app_key"))) volatile uint32_T AppValidKey;
