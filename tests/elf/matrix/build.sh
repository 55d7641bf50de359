#!/bin/sh
# Build the ELF matrix of tests/elf/matrix from its C and C++ sources, into the folder given
# (default: this folder). Needs gcc, g++, clang and clang++ (Debian: gcc g++ clang); -m32
# needs no multilib here, the programs are freestanding.
#
#   {c,cpp}-{gcc,clang}-dwarf{4,5}-m{32,64}-O{0,2}.elf   the 32 combinations
#   cpp-{gcc,clang}-dwarf{4,5}-types.elf                C++ with type units (-fdebug-types-section):
#                                                         .debug_types (DWARF 4), DW_UT_type (DWARF 5)
#
# The build is reproducible: relative source names, no build id, the source folder mapped to
# "." (a test compares a rebuild with the committed ELFs when the compilers are the versions
# recorded in their DW_AT_producer).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
out=$(cd "${1:-$here}" && pwd)
cd "$here"
common="-g -ffreestanding -nostdlib -static -fno-pic -fno-asynchronous-unwind-tables -Wl,--build-id=none -Wl,-e,_start -Wl,-N -Wl,--no-warn-rwx-segments -ffile-prefix-map=$here=."
cxx_only="-fno-exceptions -fno-rtti -fno-threadsafe-statics"
for compiler in gcc clang; do
    if [ "$compiler" = gcc ]; then cxx=g++; pie=-no-pie; else cxx=clang++; pie=; fi
    for dwarf in 4 5; do
        for bits in 32 64; do
            for opt in O0 O2; do
                flags="$common $pie -gdwarf-$dwarf -m$bits -$opt"
                $compiler $flags -o "$out/c-$compiler-dwarf$dwarf-m$bits-$opt.elf" wild.c wild_other.c
                $cxx $flags $cxx_only -o "$out/cpp-$compiler-dwarf$dwarf-m$bits-$opt.elf" wild.cpp wild_other.cpp
            done
        done
        $cxx $common $pie $cxx_only -gdwarf-$dwarf -m64 -O0 -fdebug-types-section \
            -o "$out/cpp-$compiler-dwarf$dwarf-types.elf" wild.cpp wild_other.cpp
    done
done
