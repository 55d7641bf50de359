// The second C++ unit of tests/elf/matrix: a variable of a class whose full description
// lives in wild.cpp's unit (clang), and a namespace that continues here.
#include "wild_cpp.h"

namespace app {
Sensor sensor;

namespace detail {
volatile uint8_t otherValue = 3;
}

__attribute__((noinline)) int32_t readOtherSensor()
{
    return sensor.read() + detail::otherValue;
}
}  // namespace app
