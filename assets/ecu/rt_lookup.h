/*
 * File: rt_lookup.h
 *
 * Shared lookup-table utilities (Simulink "sharedutils"): binary-search
 * breakpoint lookup, linear interpolation, clamped at the table ends.
 */

#ifndef RT_LOOKUP_H
#define RT_LOOKUP_H

#include "rtwtypes.h"

/* y = table(u0) over breakpoints bp0[0..maxIndex] */
extern real32_T look1_iflf_binlc(real32_T u0, const real32_T bp0[], const real32_T table[], uint32_T maxIndex);

/* y = table(u0, u1); table[i0 + i1 * stride] belongs to bp0[i0], bp1[i1]
 * (the bp0 index varies fastest in memory, as in Simulink's column-major tables) */
extern real32_T look2_iflf_binlc(real32_T u0, real32_T u1, const real32_T bp0[], const real32_T bp1[],
                                 const real32_T table[], const uint32_T maxIndex[], uint32_T stride);

#endif /* RT_LOOKUP_H */
