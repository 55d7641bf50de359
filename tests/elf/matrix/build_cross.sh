#!/bin/sh
# Build the cross-compiled ELFs of tests/elf/matrix/cross (committed: CI has no cross compilers)
# from the sources of this folder, into the folder given (default: ./cross). Debian bookworm:
#   apt-get install gcc-powerpc-linux-gnu g++-powerpc-linux-gnu gcc-arm-none-eabi gcc-m68k-linux-gnu \
#                   clang gdb-multiarch
#
#   gcc-ppc    powerpc-linux-gnu-gcc 12: 32-bit big-endian PowerPC (the byte order and SDA sections
#              (.sdata/.sbss) of MPC5xxx/SPC5 ECUs; no VLE: only NXP's and HighTec's compilers emit it)
#   clang-ppc  clang 14 --target=powerpc-unknown-eabi, linked by powerpc-linux-gnu-ld: big-endian
#              DWARF 5 with .debug_str_offsets/.debug_addr, DW_AT_data_bit_offset from DWARF 4 on
#   gcc-arm    arm-none-eabi-gcc 12, Cortex-M4F, Thumb-2: bare-metal, little-endian, short enums
#   gcc-m68k   m68k-linux-gnu-gcc 12: big-endian with 2-byte alignment of 32-bit types (bitfields
#              that straddle a 32-bit boundary without being packed)
#
#   {c,cpp}-{compiler}-{target}-dwarf{2,3,4,5}-O{0,2}.elf: C is wild.c + wild_other.c + ecu.c,
#   C++ wild.cpp + wild_other.cpp; a selection where every DWARF version meets gcc's big- and
#   little-endian targets (DWARF 2/3 write DW_AT_bit_offset, 4/5 DW_AT_data_bit_offset (gcc 12:
#   5 only)). Linked with ecu.ld like an ECU: code, constants, .cal and .epk in flash at FLASH,
#   variables in RAM at RAM (their initial values in flash). stripped/: two without DWARF.
#
# Then `WB_RECORD_CROSS_GDB=1 pytest tests/elf/test_matrix.py -k cross_record -n 0` records in
# cross/gdb.json where gdb-multiarch finds every object (the truth the tests compare with).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "${1:-$here/cross}"
out=$(cd "${1:-$here/cross}" && pwd)
cd "$here"
link="-T ecu.ld -z max-page-size=16 --build-id=none -e _start"
cflags="-g -ffreestanding -fno-pic -fno-asynchronous-unwind-tables -ffile-prefix-map=$here=."
cxx_only="-fno-exceptions -fno-rtti -fno-threadsafe-statics"
build() {  # language compiler target dwarf opt
    name="$out/$1-$2-$3-dwarf$4-$5.elf"
    if [ "$1" = c ]; then sources="wild.c wild_other.c ecu.c"; extra=; else sources="wild.cpp wild_other.cpp"; extra=$cxx_only; fi
    case $3 in
        ppc) prefix=powerpc-linux-gnu; flags=; memory="FLASH=0x00800000 --defsym RAM=0x40000000" ;;
        arm) prefix=arm-none-eabi; flags="-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard"
             memory="FLASH=0x08000000 --defsym RAM=0x20000000" ;;
        m68k) prefix=m68k-linux-gnu; flags=; memory="FLASH=0x00010000 --defsym RAM=0x00800000" ;;
    esac
    if [ "$2" = gcc ]; then
        compiler="$prefix-gcc"; [ "$1" = c ] || compiler="$prefix-g++"
    else
        compiler="clang --target=powerpc-unknown-eabi"; [ "$1" = c ] || compiler="clang++ --target=powerpc-unknown-eabi"
    fi
    objects=$(mktemp -d)
    for source in $sources; do
        $compiler $cflags $flags $extra -gdwarf-$4 -$5 -c -o "$objects/${source%.*}.o" "$source"
    done
    # shellcheck disable=SC2086  # the words of $memory and $link are options
    $prefix-ld $link --defsym $memory -o "$name" "$objects"/*.o "$($prefix-gcc $flags -print-libgcc-file-name)"
    rm -r "$objects"
}
build c gcc ppc 2 O0; build c gcc ppc 3 O2; build c gcc ppc 4 O0; build c gcc ppc 5 O2
build cpp gcc ppc 3 O0; build cpp gcc ppc 5 O2
build c clang ppc 4 O2; build c clang ppc 5 O0; build cpp clang ppc 5 O2
build c gcc arm 2 O2; build c gcc arm 3 O0; build c gcc arm 4 O2; build c gcc arm 5 O0
build cpp gcc arm 2 O0; build cpp gcc arm 4 O2
build c gcc m68k 2 O0; build c gcc m68k 5 O2
# stripped of their DWARF: the .symtab of a big-endian and of a Thumb ELF
mkdir -p "$out/stripped"
powerpc-linux-gnu-objcopy --strip-debug "$out/c-gcc-ppc-dwarf4-O0.elf" "$out/stripped/c-gcc-ppc-dwarf4-O0.elf"
arm-none-eabi-objcopy --strip-debug "$out/c-gcc-arm-dwarf4-O2.elf" "$out/stripped/c-gcc-arm-dwarf4-O2.elf"
