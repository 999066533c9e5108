// Ensembles: many independent meshes of one domain, member k from a seed derived from (S, k).
// Each member is written atomically with a JSON sidecar (its run report, file size and CRC-32);
// a member whose files are complete and match is skipped when the command is run again, so a
// killed run resumes where it stopped. The summary (ParaView collection and ensemble.json) is
// written from the sidecars.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>

#include "froth/domain.hpp"
#include "froth/mesh.hpp"

namespace froth {

struct EnsembleOptions {
  std::string input;  // the domain as given on the command line
  // Every member's options (defaults as for one mesh), with `mesh.seed` the ensemble's seed S:
  // member k is made with seed member_seed(S, k). r must be given (not a cell count).
  MeshOptions mesh;
  size_t members = 0;
  std::filesystem::path dir;
  std::string command;     // the exact command line, for the record
  int rank = 0, ranks = 1; // this process builds the members k with k % ranks == rank
  std::function<void(const std::string& stage, double fraction)> progress;  // "members", the fraction begun
};

// The seed of member k: Philox4x64 keyed by S (stream "ensemble") at counter k. `froth mesh
// INPUT -r R --seed member_seed(S, k)` gives member k byte for byte.
uint64_t member_seed(uint64_t seed, size_t k);
std::string member_file(size_t k);  // member_00000.vtu, ...

struct EnsembleProgress {
  size_t built = 0, resumed = 0;
  size_t failed = 0;  // members that could not be meshed (DIR/member_K.failed.json says why)
};

// Removes the temporary files a killed run left in opt.dir, and refuses (Usage) a folder holding
// members made with other inputs (another r, seed, input or options), so that one folder never
// mixes two ensembles; with `overwrite` it removes that ensemble's files instead. Files froth
// does not name (member_*, ensemble.json, ensemble.pvd) are left alone. Call on one rank, before
// any rank builds.
// The options are checked first (check_mesh_options), so a bad run touches nothing. Then the
// folder is made and locked (DIR/.froth-lock, flock): while the returned lock lives, another
// froth ensemble on the folder is refused (Usage: the folder is in use), so two runs never
// delete each other's temporary files.
class FolderLock {
 public:
  FolderLock() = default;
  explicit FolderLock(int fd) : fd_(fd) {}
  FolderLock(FolderLock&& o) noexcept : fd_(o.fd_) { o.fd_ = -1; }
  FolderLock& operator=(FolderLock&& o) noexcept;
  ~FolderLock();

 private:
  int fd_ = -1;
};
[[nodiscard]] FolderLock prepare_ensemble_folder(const Domain& domain, const EnsembleOptions& opt, bool overwrite);

// Builds this rank's members that are not already complete and valid in opt.dir.
EnsembleProgress build_members(const Domain& domain, const EnsembleOptions& opt);

// Writes DIR/ensemble.pvd and DIR/ensemble.json from the members' sidecars (each must exist, or
// its member's failure note: failed members are listed, not summarised). Returns the failure
// notes' exit codes, in member order.
std::vector<int> write_ensemble_summary(const Domain& domain, const EnsembleOptions& opt,
                                        const EnsembleProgress& progress);

}  // namespace froth
