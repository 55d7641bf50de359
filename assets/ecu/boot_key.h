/*
 * File: boot_key.h
 *
 * Keys shared by the boot code and the application (thesis 5.4). The boot
 * starts the application only while APP_VALID_KEY is stored at
 * APP_VALID_KEY_ADDRESS (first word of the SHARED flash sector); flashing the
 * application erases the key first and writes it again after a verified
 * programming, so an interrupted flash leaves the ECU in boot.
 */

#ifndef BOOT_KEY_H
#define BOOT_KEY_H

#define APP_VALID_KEY 0x5AA5C33CU         /* 32-bit word, little endian */
#define APP_VALID_KEY_ADDRESS 0x00FE0000U /* .app_key, NOLOAD: never part of the s19 */
#define FLASH_ERASED_WORD 0xFFFFFFFFU

#define CAL_VALID_KEY 0xC33C5AA5U /* last word of the CALIB trailer at 0xFDFFF0 */

#endif /* BOOT_KEY_H */
