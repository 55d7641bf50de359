// C++ fixture of tests/elf/matrix: namespaces, classes, inheritance (several bases, several
// levels, a base reached by its name), static members, function-local statics in functions
// and methods, anonymous unions in classes, an anonymous namespace. wild_other.cpp is the
// second unit: under clang's default -fno-standalone-debug it only declares app::Sensor.
#include "wild_cpp.h"

namespace app {

struct Base {
    uint16_t baseId;
    float baseGain;
};

struct Mixin {
    int32_t mixinValue;
    uint8_t flags;
};

// two bases, then one more level
struct Derived : Base, Mixin {
    uint32_t derivedOnly;
};

struct MostDerived : Derived {
    int16_t leaf[3];
    union {
        uint32_t raw;
        struct {
            uint32_t lowBits : 12;
            uint32_t highBits : 20;
        };
    };
};

class Controller {
public:
    static uint32_t instances;
    static float limits[4];
    float setpoint;
    uint32_t step(uint32_t input);
private:
    int32_t integral;
};

uint32_t Controller::instances = 1;
float Controller::limits[4] = {1.0f, 2.0f, 3.0f, 4.0f};

namespace detail {
volatile uint16_t nestedValue = 7;
volatile int64_t counters[2][3];
}

int32_t Sensor::read()  // the key function: the unit that holds it describes the class in full
{
    return raw;
}

volatile MostDerived mostDerived;
volatile Derived derived;
Controller controller;

__attribute__((noinline)) uint32_t Controller::step(uint32_t input)
{
    static volatile uint32_t calls;
    calls++;
    integral += (int32_t)input;
    return (uint32_t)integral + instances + calls;
}

}  // namespace app

namespace {
volatile uint8_t hiddenInAnonymous = 9;
}

volatile uint32_t plainGlobal;

__attribute__((noinline)) uint32_t freeFunction()
{
    static volatile uint16_t freeCalls;
    freeCalls++;
    return freeCalls + hiddenInAnonymous;
}

extern "C" void _start()
{
    for (;;) {
        plainGlobal += app::controller.step(freeFunction());
        app::mostDerived.lowBits = 3;
        app::mostDerived.baseId = 2;
        app::derived.mixinValue = app::detail::nestedValue + (int32_t)app::detail::counters[1][2];
        app::Controller::limits[1] += 1.0f;
        plainGlobal += (uint32_t)app::readOtherSensor();
    }
}
