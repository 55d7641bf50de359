/* Types shared by wild.c and wild_other.c: what A2L tools meet in C code from the wild. */
#ifndef WILD_H
#define WILD_H
#include <stdint.h>

/* a peripheral register: the whole word, or its bits through an anonymous struct (C11) */
typedef union {
    uint32_t Value;
    struct {
        uint32_t Enable : 1;
        uint32_t Mode : 3;
        uint32_t : 4;
        uint32_t Prescaler : 8;
        uint32_t Reserved : 16;
    };
} tReg;

/* anonymous members at several depths, with named siblings */
typedef struct {
    uint8_t kind;
    union {
        float asFloat;
        int32_t asInt;
        struct {
            uint16_t low;
            uint16_t high;
        };
    };
    struct {
        uint8_t flagA : 1;
        uint8_t flagB : 1;
        uint8_t count : 6;
    };
    int16_t tail[3];
} tVariant;

/* the struct of a map: axes and values */
typedef struct {
    float xAxis[8];
    float yAxis[4];
    int16_t values[4][8];
} tMap;

extern volatile tReg ctrlReg;
extern volatile tVariant variant;
extern volatile int32_t sharedCounter;

void wild_other_step(void);
#endif
