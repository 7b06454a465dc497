// A seeded random source whose numbers are the same on every platform and
// compiler: splitmix64 (Steele, Lea, Flood 2014) turned into doubles by bit
// arithmetic, normals by Box–Muller. <random>'s distributions are
// implementation-defined, which would break byte-identical outputs.
#pragma once

#include <cmath>
#include <cstdint>

namespace syn {

class SplitMix64 {
 public:
  explicit SplitMix64(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) from the top 53 bits.
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  double uniform(double low, double high) { return low + (high - low) * uniform(); }
  // Standard normal (Box–Muller; one of the pair is discarded for simplicity).
  double normal() {
    const double radius = std::sqrt(-2.0 * std::log(1.0 - uniform()));
    return radius * std::cos(2.0 * M_PI * uniform());
  }

 private:
  uint64_t state_;
};

}  // namespace syn
