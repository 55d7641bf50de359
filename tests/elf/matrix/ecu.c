/* Third C unit of the cross-compiled ELFs (build_cross.sh, tests/elf/test_matrix.py): what an
   ECU's ELF holds beyond wild.c: bitfields in 8-, 16- and 32-bit storage units, a signed one,
   ones of a packed frame that straddle a 32-bit boundary (their bit order is the target's: the
   trap of big-endian ECUs), double, 64-bit integers, an enum (one byte under arm-none-eabi's
   short enums), a pointer (4 bytes), a calibration in flash and the EPK in a section of its own. */
#include <stdint.h>

/* signed, a value of two bytes: enumerators in 1-, 2- and sdata forms, read in the target's byte order */
typedef enum { GEAR_FAULT = -1, GEAR_PARK, GEAR_REVERSE, GEAR_NEUTRAL, GEAR_DRIVE, GEAR_SERVICE = 0x1234 } tGear;

typedef struct {
    uint8_t ready : 1;
    uint8_t level : 3;
    uint16_t phase : 5;
    uint16_t sector : 9;
    int32_t offset : 7;
    uint32_t window : 20;
} tStatus;

/* a CAN frame's layout: packed, so its 32-bit fields lie across 32-bit boundaries */
typedef struct __attribute__((packed)) {
    uint8_t id;
    uint8_t kind : 4;
    uint32_t value : 24;
    uint32_t crc : 12;
} tFrame;

/* a field no 32-bit unit holds (bits 3 to 32): update --types can give it no BIT_MASK */
typedef struct __attribute__((packed)) {
    uint8_t low : 3;
    uint32_t wide : 30;
} tWide;

volatile tStatus status;
volatile tWide wide;
volatile tFrame frame;
volatile double torque;
volatile int64_t energy = -5;
volatile uint64_t odometer;
volatile tGear gear;
volatile uint8_t *volatile bufferPointer;

/* calibration data in flash, as ECU linker scripts place them */
__attribute__((used, section(".cal"))) const double calibDouble = 1.25;
__attribute__((used, section(".cal"))) const int16_t calibTable[4] = {-1, 2, -3, 4};

/* the EPK string: in a section of its own at a fixed place in flash */
__attribute__((used, section(".epk"))) const char epkText[] = "ECU-MATRIX 1.0";
