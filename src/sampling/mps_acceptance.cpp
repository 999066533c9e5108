// A round's candidates decided in arrival order, in parallel and across MPI ranks, then numbered
// as seeds (sampling/mps_sampler.hpp).
#include "sampling/mps_sampler.hpp"

namespace froth::mps {

void Sampler::accept_round(Darts& round) {
  s_.stats.darts += round.thrown;
  Round round_set;
  round_set.all = concatenate(round.parts);
  if (partition_) add_neighbours_candidates(round_set);
  const std::vector<Candidate>& all = round_set.all;
  s_.stats.candidates += all.size();
  const std::vector<uint8_t> accepted = accept_in_arrival_order(round_set);
  // New seeds are numbered in Morton order of their cubes, so the seeds that neighbour
  // queries read together lie together in memory (the arrival order scatters them). A
  // neighbour's accepted candidates are this rank's halo seeds.
  std::vector<std::pair<uint64_t, uint32_t>> order;
  for (size_t c = 0; c < all.size(); ++c)
    if (accepted[c]) order.push_back({morton(all[c].base), uint32_t(c)});
  std::sort(order.begin(), order.end());
  for (const auto& [key, c] : order) {
    cube_entry(all[c].base) = int32_t(s_.seeds.size());
    s_.seeds.push_back(all[c].p);
  }
}

void Sampler::add_neighbours_candidates(Round& rs) {
  auto pack = [&](bool lower) {
    Communicator::Bytes out;
    for (const Candidate& c : rs.all) {
      const int k = layer_of(c.base);
      if (lower ? k < owned_begin_ + kSamplingHaloLayers : k >= owned_end_ - kSamplingHaloLayers) {
        const auto* b = reinterpret_cast<const uint8_t*>(&c);
        out.insert(out.end(), b, b + sizeof(Candidate));
      }
    }
    return out;
  };
  Communicator::Bytes below, above;
  partition_->comm->exchange_with_neighbours(pack(true), pack(false), below, above);
  ++partition_->exchanges;
  rs.source.assign(rs.all.size(), 0);
  for (const auto* bytes : {&below, &above}) {
    const size_t n = bytes->size() / sizeof(Candidate);
    const size_t at = rs.all.size();
    rs.all.resize(at + n);
    if (n > 0) std::memcpy(static_cast<void*>(rs.all.data() + at), bytes->data(), n * sizeof(Candidate));
    rs.source.resize(at + n, bytes == &below ? 1 : 2);
  }
  std::vector<uint32_t> perm(rs.all.size());
  for (size_t i = 0; i < perm.size(); ++i) perm[i] = uint32_t(i);
  std::sort(perm.begin(), perm.end(), [&](uint32_t a, uint32_t b) { return by_arrival(rs.all[a], rs.all[b]); });
  std::vector<Candidate> sorted(perm.size());
  std::vector<uint8_t> source(perm.size());
  for (size_t i = 0; i < perm.size(); ++i) sorted[i] = rs.all[perm[i]], source[i] = rs.source[perm[i]];
  rs.all = std::move(sorted);
  rs.source = std::move(source);
  // Each side's candidates keep their relative (arrival) order, so both ranks list the traded
  // ones in the same order.
  for (size_t c = 0; c < rs.all.size(); ++c) {
    const int k = layer_of(rs.all[c].base);
    if (rs.source[c] == 1) rs.from_lower.push_back(uint32_t(c));
    else if (rs.source[c] == 2) rs.from_upper.push_back(uint32_t(c));
    else {
      if (k < owned_begin_ + kSamplingHaloLayers) rs.send_lower.push_back(uint32_t(c));
      if (k >= owned_end_ - kSamplingHaloLayers) rs.send_upper.push_back(uint32_t(c));
    }
  }
}

std::vector<uint8_t> Sampler::accept_in_arrival_order(const Round& rs) {
  enum : uint8_t { Undecided, Accepted, Rejected };
  const std::vector<Candidate>& all = rs.all;
  const size_t n = all.size();
  // Candidates bucketed in cubes of side r over their bounding box (counting sort). When the
  // box has many more cubes than candidates (late rounds, or a domain that fills little of its
  // box) the cubes are hashed into 2n slots, so a round costs O(n); cubes that share a slot
  // only add candidates the exact test then skips.
  Box box{all.empty() ? Vec3{} : all[0].p, all.empty() ? Vec3{} : all[0].p};
  for (const Candidate& c : all)
    for (int a = 0; a < 3; ++a) box.lo[a] = std::min(box.lo[a], c.p[a]), box.hi[a] = std::max(box.hi[a], c.p[a]);
  const int nx = std::max(1, int(std::ceil(box.size().x / r_))), ny = std::max(1, int(std::ceil(box.size().y / r_))),
            nz = std::max(1, int(std::ceil(box.size().z / r_)));
  auto cell = [&](Vec3 p, int& i, int& j, int& k) {
    i = std::clamp(int((p.x - box.lo.x) / r_), 0, nx - 1);
    j = std::clamp(int((p.y - box.lo.y) / r_), 0, ny - 1);
    k = std::clamp(int((p.z - box.lo.z) / r_), 0, nz - 1);
  };
  const size_t cubes = size_t(nx) * ny * nz;
  const bool hashed = cubes > 4 * n;
  const size_t slots = hashed ? std::bit_ceil(2 * n) : cubes;
  auto slot = [&](int i, int j, int k) {
    if (!hashed) return (size_t(k) * ny + j) * nx + i;
    return size_t((uint64_t(i) * 73856093u) ^ (uint64_t(j) * 19349663u) ^ (uint64_t(k) * 83492791u)) & (slots - 1);
  };
  std::vector<uint32_t> begin(slots + 1, 0), key(n);
  for (size_t c = 0; c < n; ++c) {
    int i, j, k;
    cell(all[c].p, i, j, k);
    key[c] = uint32_t(slot(i, j, k));
    ++begin[key[c] + 1];
  }
  for (size_t b = 1; b < begin.size(); ++b) begin[b] += begin[b - 1];
  // The candidates again in slot order, each slot's in arrival order, and everything the
  // passes read kept in that order: a candidate's neighbours are then read from nearby memory
  // (in arrival order they are scattered in space, and their reads missed the cache: half of
  // a round's time).
  struct Entry {
    Candidate c;
    uint32_t index;  // in `all`
  };
  std::vector<Entry> entry(n);
  std::vector<uint32_t> at(n);  // entry of each candidate of `all`
  {
    std::vector<uint32_t> fill(begin.begin(), begin.end() - 1);
    for (size_t c = 0; c < n; ++c) entry[fill[key[c]]++] = {all[c], uint32_t(c)};
  }
#pragma omp parallel for schedule(dynamic, 4096)
  for (size_t b = 0; b < slots; ++b) {
    std::sort(entry.begin() + begin[b], entry.begin() + begin[b + 1],
              [](const Entry& x, const Entry& y) { return by_arrival(x.c, y.c); });
    for (uint32_t e = begin[b]; e < begin[b + 1]; ++e) at[entry[e].index] = e;
  }
  std::vector<std::atomic<uint8_t>> state(n);  // by entry
  for (auto& s : state) s.store(Undecided, std::memory_order_relaxed);
  // The pass in which an entry was last found blocked (0: none). A blocked entry reached again
  // in that pass through another's recursion answers at once: otherwise a cluster of k
  // mutually conflicting candidates whose earliest waits for a neighbour rank's decision is
  // walked along every descending chain, some 2^k times, up to the depth bound (commit
  // 811beed). The answer is only postponed to a later
  // pass, and the outcome, greedy in arrival order, does not depend on when it is decided.
  std::vector<std::atomic<uint32_t>> blocked_in_pass(n);
  for (auto& b : blocked_in_pass) b.store(0, std::memory_order_relaxed);
  uint32_t pass = 0;
  constexpr int kDecideDepth = 16;
  for (;;) {
    bool undecided = n > 0, progress = true;
    while (undecided && progress) {
      undecided = progress = false;
      ++pass;
      size_t lookups = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(|| : undecided, progress) reduction(+ : lookups)
      for (size_t e = 0; e < n; ++e) {
        if (state[e].load(std::memory_order_relaxed) != Undecided) continue;
        if (!rs.source.empty() && rs.source[entry[e].index] != 0) continue;  // a neighbour decides it
        // Decides entry f if it can, deciding its undecided earlier conflicting candidates
        // first, to a bounded depth: in bucket order those are often not visited yet, and
        // leaving them to the next pass took 4 to 6 passes.
        auto decide = [&](auto& self, uint32_t f, int depth) -> uint8_t {
          ++lookups;
          const uint8_t known = state[f].load(std::memory_order_acquire);
          if (known != Undecided) return known;
          if (!rs.source.empty() && rs.source[entry[f].index] != 0) return Undecided;  // until traded
          // (A pass's own visit to an entry always looks again: its blockers may be decided by now.)
          if (depth < kDecideDepth && blocked_in_pass[f].load(std::memory_order_relaxed) == pass) return Undecided;
          const Candidate& me = entry[f].c;
          int ci, cj, ck;
          cell(me.p, ci, cj, ck);
          bool blocked = false;
          for (int k = std::max(0, ck - 1); k <= std::min(nz - 1, ck + 1); ++k)
            for (int j = std::max(0, cj - 1); j <= std::min(ny - 1, cj + 1); ++j)
              for (int i = std::max(0, ci - 1); i <= std::min(nx - 1, ci + 1); ++i) {
                const size_t b = slot(i, j, k);
                for (uint32_t o = begin[b]; o < begin[b + 1]; ++o) {
                  const Candidate& other = entry[o].c;
                  if (!by_arrival(other, me)) break;  // only earlier arrivals matter (in order in a slot)
                  if (other.base != me.base && norm2(other.p - me.p) >= r2_) continue;
                  const uint8_t so = depth > 0 ? self(self, o, depth - 1) : state[o].load(std::memory_order_acquire);
                  if (so == Accepted) {
                    state[f].store(Rejected, std::memory_order_release);
                    progress = true;
                    return Rejected;
                  }
                  blocked |= so == Undecided;
                }
              }
          if (blocked) {
            blocked_in_pass[f].store(pass, std::memory_order_relaxed);
            return Undecided;
          }
          state[f].store(Accepted, std::memory_order_release);
          progress = true;
          return Accepted;
        };
        if (decide(decide, uint32_t(e), kDecideDepth) == Undecided) undecided = true;
      }
      s_.stats.decision_lookups += lookups;
    }
    if (!partition_) break;
    // Trade decisions with the neighbours, then stop when no rank has an undecided candidate
    // (the trade before that last check delivered the final ones).
    auto states = [&](const std::vector<uint32_t>& candidates) {
      Communicator::Bytes out(candidates.size());
      for (size_t k = 0; k < candidates.size(); ++k) out[k] = state[at[candidates[k]]].load(std::memory_order_relaxed);
      return out;
    };
    Communicator::Bytes below, above;
    partition_->comm->exchange_with_neighbours(states(rs.send_lower), states(rs.send_upper), below, above);
    ++partition_->exchanges;
    for (size_t k = 0; k < rs.from_lower.size(); ++k) state[at[rs.from_lower[k]]].store(below.at(k));
    for (size_t k = 0; k < rs.from_upper.size(); ++k) state[at[rs.from_upper[k]]].store(above.at(k));
    if (!anywhere(undecided)) break;
  }
  std::vector<uint8_t> accepted(n);
  for (size_t c = 0; c < n; ++c) accepted[c] = state[at[c]].load(std::memory_order_relaxed) == Accepted;
  return accepted;
}

}  // namespace froth::mps
