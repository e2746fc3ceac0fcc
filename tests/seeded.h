// Seeded random numbers the tests share (unity builds: a helper defined in two files of one
// batch would be defined twice). From the raw std::mt19937_64 output only, so the same seed
// gives the same draws with every standard library.
#pragma once

#include <random>

namespace octtest {

// Uniform in [0, 1), 53 random bits.
inline double u01(std::mt19937_64& rng) { return double(rng() >> 11) * 0x1p-53; }

}  // namespace octtest
