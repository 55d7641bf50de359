// What wild.cpp and wild_other.cpp share.
#ifndef WILD_CPP_H
#define WILD_CPP_H
#include <stdint.h>

namespace app {
class Sensor {
public:
    virtual int32_t read();
    int32_t raw;
    float scale;
};

int32_t readOtherSensor();
}  // namespace app
#endif
