/*
 * File: rtwtypes.h
 *
 * Embedded Coder fixed-width types for the FLCU demo application.
 * Target: 32-bit ECU (int 32 bits, long 32 bits, pointer 32 bits); the demo is
 * built with the host gcc in -m32 mode, the real HDS9 uses an MPC5777C.
 */

#ifndef RTWTYPES_H
#define RTWTYPES_H

typedef signed char int8_T;
typedef unsigned char uint8_T;
typedef short int16_T;
typedef unsigned short uint16_T;
typedef int int32_T;
typedef unsigned int uint32_T;
typedef long long int64_T;
typedef unsigned long long uint64_T;
typedef float real32_T;
typedef double real64_T;
typedef double real_T;
typedef double time_T;
typedef unsigned char boolean_T;
typedef int int_T;
typedef unsigned int uint_T;
typedef char char_T;
typedef unsigned char uchar_T;
typedef char_T byte_T;

#ifndef TRUE
#define TRUE (1U)
#endif

#ifndef FALSE
#define FALSE (0U)
#endif

#endif /* RTWTYPES_H */
