// Counter-based randomness (Random123 Philox4x64-10): every random number is a pure function of
// (seed, stream, counter), so results depend on neither threads, ranks nor the order of work.
#pragma once
#include <Random123/philox.h>

#include <array>
#include <cstdint>

namespace froth {

enum class RandomStream : uint64_t { Sampling = 1, Ensemble = 2, Protection = 3, Graded = 4, Interfaces = 5, Cracks = 6 };

class CounterRng {
 public:
  using Philox = r123::Philox4x64;
  CounterRng(uint64_t seed, RandomStream stream) : key_{{seed, static_cast<uint64_t>(stream)}} {}

  std::array<uint64_t, 4> words(uint64_t c0, uint64_t c1, uint64_t c2, uint64_t c3) const {
    Philox::ctr_type ctr = {{c0, c1, c2, c3}};
    Philox::ctr_type out = Philox()(ctr, key_);
    return {out[0], out[1], out[2], out[3]};
  }

  // Uniform in (0, 1) with 53 random bits; never exactly 0 or 1.
  static double unit(uint64_t w) { return (static_cast<double>(w >> 11) + 0.5) * 0x1p-53; }

 private:
  Philox::key_type key_;
};

}  // namespace froth
