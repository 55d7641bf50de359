/* C fixture of tests/elf/matrix: anonymous unions and structs, bitfields, function-local
   statics (unique and ambiguous), file statics, arrays for CURVE/MAP/AXIS_PTS objects. */
#include "wild.h"

volatile tReg ctrlReg;
volatile tVariant variant;
volatile int32_t sharedCounter;

/* calibrations: a curve with its axis, a map, a shared axis, a value block */
volatile const float curveAxis[6] = {0, 10, 20, 30, 40, 50};
volatile const int16_t curveValues[6] = {1, 2, 3, 4, 5, 6};
volatile const tMap engineMap = {{0}, {0}, {{0}}};
volatile const uint16_t sharedAxis[5] = {0, 100, 200, 300, 400};
volatile const uint8_t valueBlock[3][4] = {{1, 2, 3, 4}};
volatile const float gain = 2.5f;
volatile uint64_t bigCounter;
volatile int8_t signedMatrix[2][3][4];

/* a file static with the same name as one in wild_other.c */
static volatile uint16_t fileLocal = 1;

/* a function static whose name is unique in the program */
__attribute__((noinline)) uint32_t wild_tick(void)
{
    static volatile uint32_t tickCount;
    static volatile uint8_t history[4];
    /* "ambiguous": wild_other.c's wild_other_step has a static of this name too */
    static volatile uint16_t ambiguous = 3;
    tickCount++;
    history[tickCount & 3] = (uint8_t)tickCount;
    ambiguous++;
    fileLocal++;
    return tickCount;
}

/* two functions of this file with a static of the same name */
__attribute__((noinline)) void wild_filter(void)
{
    static volatile float state = 0.5f;
    state = state * 0.9f + (float)ctrlReg.Mode;
}

__attribute__((noinline)) void wild_limit(void)
{
    static volatile float state = 1.5f;
    if (state > 100.0f) {
        state = 100.0f;
    }
    ctrlReg.Enable = 1;
    variant.count = 5;
}

void _start(void)
{
    for (;;) {
        wild_tick();
        wild_filter();
        wild_limit();
        wild_other_step();
        sharedCounter += gain > 1.0f;
        bigCounter += curveValues[1] + engineMap.values[1][2] + sharedAxis[3] + valueBlock[0][1] + curveAxis[2];
        signedMatrix[1][2][3]++;
    }
}
