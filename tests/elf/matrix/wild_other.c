/* The second compile unit of the C fixture: a file static and a function static whose
   names wild.c uses too. */
#include "wild.h"

static volatile uint16_t fileLocal = 2;

__attribute__((noinline)) void wild_other_step(void)
{
    static volatile uint16_t ambiguous = 4;
    static volatile int32_t otherOnly;
    ambiguous++;
    otherOnly += ctrlReg.Prescaler;
    fileLocal++;
    sharedCounter++;
}
