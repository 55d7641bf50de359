/*
 * File: rt_lookup.c
 *
 * Shared lookup-table utilities (Simulink "sharedutils"). All arithmetic is
 * single precision; the Python twin (workbench/sim/flcu/rt.py) repeats it
 * operation by operation.
 */

#include "rt_lookup.h"

/* Index i and fraction f such that u lies between bp[i] and bp[i + 1]:
 * below the table f = 0 at i = 0, above it f = 1 at i = maxIndex - 1. */
static uint32_T plook_binlc(real32_T u, const real32_T bp[], uint32_T maxIndex, real32_T *fraction)
{
  uint32_T iLeft;
  uint32_T iRght;
  uint32_T bpIdx;

  if (u <= bp[0U]) {
    *fraction = 0.0F;
    return 0U;
  }
  if (u >= bp[maxIndex]) {
    *fraction = 1.0F;
    return maxIndex - 1U;
  }
  iLeft = 0U;
  iRght = maxIndex;
  while (iRght - iLeft > 1U) {
    bpIdx = (iLeft + iRght) >> 1U;
    if (u < bp[bpIdx]) {
      iRght = bpIdx;
    } else {
      iLeft = bpIdx;
    }
  }
  *fraction = (u - bp[iLeft]) / (bp[iLeft + 1U] - bp[iLeft]);
  return iLeft;
}

real32_T look1_iflf_binlc(real32_T u0, const real32_T bp0[], const real32_T table[], uint32_T maxIndex)
{
  real32_T frac;
  uint32_T idx = plook_binlc(u0, bp0, maxIndex, &frac);
  return table[idx] + frac * (table[idx + 1U] - table[idx]);
}

real32_T look2_iflf_binlc(real32_T u0, real32_T u1, const real32_T bp0[], const real32_T bp1[],
                          const real32_T table[], const uint32_T maxIndex[], uint32_T stride)
{
  real32_T frac0;
  real32_T frac1;
  real32_T yLow;
  real32_T yHigh;
  uint32_T idx0 = plook_binlc(u0, bp0, maxIndex[0U], &frac0);
  uint32_T idx1 = plook_binlc(u1, bp1, maxIndex[1U], &frac1);
  uint32_T base = idx0 + idx1 * stride;

  yLow = table[base] + frac0 * (table[base + 1U] - table[base]);
  yHigh = table[base + stride] + frac0 * (table[base + stride + 1U] - table[base + stride]);
  return yLow + frac1 * (yHigh - yLow);
}
