#!/bin/sh
# Build the cross-compiled ELFs of tests/elf/matrix/cross (committed: CI has no cross compilers)
# from the sources of this folder, into the folder given (default: ./cross). Debian bookworm:
#   apt-get install gcc-powerpc-linux-gnu g++-powerpc-linux-gnu gcc-arm-none-eabi gcc-m68k-linux-gnu gdb-multiarch
#
#   ppc   powerpc-linux-gnu-gcc 12: 32-bit big-endian PowerPC (the byte order and SDA sections
#         (.sdata/.sbss) of MPC5xxx/SPC5 ECUs; no VLE: only NXP's and HighTec's compilers emit it)
#   arm   arm-none-eabi-gcc 12, Cortex-M4F, Thumb-2: bare-metal, little-endian, short enums
#   m68k  m68k-linux-gnu-gcc 12: big-endian with 2-byte alignment of 32-bit types (bitfields
#         that straddle a 32-bit boundary without being packed)
#
#   {c,cpp}-{ppc,arm,m68k}-dwarf{2,3,4,5}-O{0,2}.elf: C is wild.c + wild_other.c + ecu.c,
#   C++ wild.cpp + wild_other.cpp; a selection where every DWARF version meets every target
#   (DWARF 2/3 write DW_AT_bit_offset, 4/5 DW_AT_data_bit_offset (gcc 12: 5 only)).
#   Linked with ecu.ld like an ECU: code, constants, .cal and .epk in flash at FLASH, variables
#   in RAM at RAM (their initial values in flash). stripped/: two of them without DWARF (.symtab only).
#
# Then `WB_RECORD_CROSS_GDB=1 pytest tests/elf/test_matrix.py -k cross_record -n 0` records in
# cross/gdb.json where gdb-multiarch finds every object (the truth the tests compare with).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "${1:-$here/cross}"
out=$(cd "${1:-$here/cross}" && pwd)
cd "$here"
common="-g -ffreestanding -nostdlib -static -fno-pic -fno-asynchronous-unwind-tables -Wl,--build-id=none -Wl,-e,_start -T ecu.ld -Wl,-z,max-page-size=16 -ffile-prefix-map=$here=."
cxx_only="-fno-exceptions -fno-rtti -fno-threadsafe-statics"
build() {  # language target dwarf opt
    case $2 in
        ppc) cc="powerpc-linux-gnu-gcc"; cxx="powerpc-linux-gnu-g++"; memory="FLASH=0x00800000,--defsym,RAM=0x40000000" ;;
        arm) flags="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard"
             cc="arm-none-eabi-gcc $flags"; cxx="arm-none-eabi-g++ $flags"; memory="FLASH=0x08000000,--defsym,RAM=0x20000000" ;;
        m68k) cc="m68k-linux-gnu-gcc"; cxx=; memory="FLASH=0x00010000,--defsym,RAM=0x00800000" ;;
    esac
    flags="$common -Wl,--defsym,$memory -gdwarf-$3 -$4"
    if [ "$1" = c ]; then
        $cc $flags -o "$out/c-$2-dwarf$3-$4.elf" wild.c wild_other.c ecu.c -lgcc
    else
        $cxx $flags $cxx_only -o "$out/cpp-$2-dwarf$3-$4.elf" wild.cpp wild_other.cpp -lgcc
    fi
}
build c ppc 2 O0; build c ppc 3 O2; build c ppc 4 O0; build c ppc 5 O2
build cpp ppc 3 O0; build cpp ppc 5 O2
build c arm 2 O2; build c arm 3 O0; build c arm 4 O2; build c arm 5 O0
build cpp arm 2 O0; build cpp arm 4 O2
build c m68k 2 O0; build c m68k 5 O2
# stripped of their DWARF: the .symtab of a big-endian and of a Thumb ELF
mkdir -p "$out/stripped"
powerpc-linux-gnu-objcopy --strip-debug "$out/c-ppc-dwarf4-O0.elf" "$out/stripped/c-ppc-dwarf4-O0.elf"
arm-none-eabi-objcopy --strip-debug "$out/c-arm-dwarf4-O2.elf" "$out/stripped/c-arm-dwarf4-O2.elf"
