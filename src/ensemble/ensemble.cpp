// Ensembles: members built (or found complete) one after another, each written atomically with
// its sidecar, then summarised.
#include "froth/ensemble.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "common/random.hpp"
#include "froth/error.hpp"
#include "froth/io.hpp"
#include "froth/mesh.hpp"
#include "io/atomic_file.hpp"

namespace froth {
namespace {

using Json = nlohmann::ordered_json;

std::filesystem::path sidecar(const EnsembleOptions& opt, size_t k) {
  return opt.dir / fmt::format("member_{:05d}.json", k);
}

// A member that could not be meshed: why, for the summary (any rank's) and the next run.
std::filesystem::path failure_note(const EnsembleOptions& opt, size_t k) {
  return opt.dir / fmt::format("member_{:05d}.failed.json", k);
}

// CRC-32 and size of a file, or size -1 if it cannot be read.
std::pair<int64_t, uint32_t> crc_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {-1, 0};
  std::vector<char> buf(1 << 20);
  uLong crc = crc32(0L, Z_NULL, 0);
  int64_t size = 0;
  while (in) {
    in.read(buf.data(), std::streamsize(buf.size()));
    const std::streamsize got = in.gcount();
    if (got <= 0) break;
    crc = crc32(crc, reinterpret_cast<const Bytef*>(buf.data()), uInt(got));
    size += got;
  }
  return {size, uint32_t(crc)};
}

// Was the member whose sidecar is `j` made with these options, as member k? (Throws if `j` lacks
// a field.)
bool same_inputs(const EnsembleOptions& opt, const Json& j, size_t k) {
  const Json& m = j.at("member");
  const Json& in = j.at("input");
  return m.at("seed").get<uint64_t>() == member_seed(opt.mesh.seed, k) && in.at("r").get<double>() == opt.mesh.r &&
         in.at("weld").get<double>() == *opt.mesh.weld && m.at("input").get<std::string>() == opt.input &&
         m.at("quality").get<bool>() == opt.mesh.quality && in.at("grade").get<bool>() == opt.mesh.grade &&
         (!opt.mesh.grade ||
          (in.at("min_r").get<double>() == opt.mesh.min_r && in.at("max_grading").get<double>() == opt.mesh.grading));
}

// Is member k in the directory, complete, and made with these options?
bool member_done(const EnsembleOptions& opt, size_t k) {
  std::ifstream in(sidecar(opt, k));
  if (!in) return false;
  Json j;
  try {
    j = Json::parse(in);
    const Json& m = j.at("member");
    if (j.at("froth_version") != FROTH_VERSION || !same_inputs(opt, j, k)) return false;
    const auto [size, crc] = crc_of(opt.dir / member_file(k));
    return size == m.at("bytes").get<int64_t>() && crc == m.at("crc32").get<uint32_t>();
  } catch (const std::exception&) {
    return false;  // unreadable or from another version: build it again
  }
}

// A member's options, checked before the folder is touched.
void check_member_options(const Domain& domain, const EnsembleOptions& opt) {
  if (opt.mesh.cells != 0) fail(ErrorKind::Usage, "an ensemble takes r, not a cell count");
  check_mesh_options(domain, opt.mesh);
}

// The options with every default resolved (resolve_options), as the sidecars record them.
EnsembleOptions resolved(const Domain& domain, const EnsembleOptions& given) {
  check_member_options(domain, given);
  EnsembleOptions opt = given;
  opt.mesh = resolve_options(domain, given.mesh);
  return opt;
}

struct Spread {
  std::vector<double> v;
  Json json() const {
    if (v.empty()) return Json();
    double mean = 0, sd = 0;
    for (double x : v) mean += x;
    mean /= double(v.size());
    for (double x : v) sd += (x - mean) * (x - mean);
    sd = v.size() > 1 ? std::sqrt(sd / double(v.size() - 1)) : 0;
    return {{"mean", mean}, {"sd", sd}, {"min", *std::min_element(v.begin(), v.end())},
            {"max", *std::max_element(v.begin(), v.end())}};
  }
};

}  // namespace

uint64_t member_seed(uint64_t seed, size_t k) {
  return CounterRng(seed, RandomStream::Ensemble).words(uint64_t(k), 0, 0, 0)[0];
}

std::string member_file(size_t k) { return fmt::format("member_{:05d}.vtu", k); }

FolderLock& FolderLock::operator=(FolderLock&& o) noexcept {
  std::swap(fd_, o.fd_);
  return *this;
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);  // closing releases the flock
}

FolderLock prepare_ensemble_folder(const Domain& domain, const EnsembleOptions& given, bool overwrite) {
  const EnsembleOptions opt = resolved(domain, given);
  std::error_code ec;
  if (std::filesystem::exists(opt.dir, ec) && !std::filesystem::is_directory(opt.dir, ec))
    fail(ErrorKind::Io, fmt::format("{}: exists and is not a folder; name a folder for the ensemble", opt.dir.string()));
  std::filesystem::create_directories(opt.dir);
  const std::string lock_path = (opt.dir / ".froth-lock").string();
  const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) fail(ErrorKind::Io, fmt::format("{}: cannot create the folder's lock file", lock_path));
  FolderLock lock(fd);
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
    fail(ErrorKind::Usage, fmt::format("{}: the folder is in use by another froth ensemble; wait for it to end, or "
                                       "name another folder",
                                       opt.dir.string()));
  std::vector<std::filesystem::path> ours;  // the files an ensemble writes, and their temporaries
  std::string other;                       // the first member made with other inputs
  for (const auto& entry : std::filesystem::directory_iterator(opt.dir)) {
    const std::string name = entry.path().filename().string();
    const bool summary = name.rfind("ensemble.json", 0) == 0 || name.rfind("ensemble.pvd", 0) == 0;
    if (!summary && name.rfind("member_", 0) != 0) continue;  // not froth's: left alone
    if (name.find(".tmp") != std::string::npos) {
      std::filesystem::remove(entry.path(), ec);  // a killed run's leftover, never renamed into place
      continue;
    }
    ours.push_back(entry.path());
    size_t k = 0;
    if (!other.empty() || summary || std::sscanf(name.c_str(), "member_%zu.json", &k) != 1 ||
        name != fmt::format("member_{:05d}.json", k))
      continue;
    try {
      std::ifstream in(entry.path());
      const Json j = Json::parse(in);
      if (!same_inputs(opt, j, k))
        other = fmt::format("member {} (r = {}, seed {}, input {})", k, j.at("input").at("r").get<double>(),
                            j.at("member").at("seed").get<uint64_t>(), j.at("member").at("input").get<std::string>());
    } catch (const std::exception&) {
      // A damaged sidecar is rebuilt, not a reason to refuse.
    }
  }
  if (other.empty()) return lock;
  if (!overwrite)
    fail(ErrorKind::Usage, fmt::format("{} holds an ensemble made with other inputs: {}; overwrite it (the ensemble's "
                                       "overwrite option) or name another folder",
                                       opt.dir.string(), other));
  for (const auto& path : ours) std::filesystem::remove(path);
  return lock;
}

EnsembleProgress build_members(const Domain& domain, const EnsembleOptions& given) {
  const EnsembleOptions opt = resolved(domain, given);
  std::error_code ec;
  if (std::filesystem::exists(opt.dir, ec) && !std::filesystem::is_directory(opt.dir, ec))
    fail(ErrorKind::Io, fmt::format("{}: exists and is not a folder; name a folder for the ensemble", opt.dir.string()));
  std::filesystem::create_directories(opt.dir);
  // A killed run can leave a member's temporary file (member_00002.vtu.tmp1234) behind: it was
  // never renamed into place, so it is not a member; remove such leftovers of this rank's members.
  for (const auto& entry : std::filesystem::directory_iterator(opt.dir)) {
    const std::string name = entry.path().filename().string();
    size_t k = 0;
    if (name.rfind("member_", 0) == 0 && name.find(".tmp") != std::string::npos &&
        std::sscanf(name.c_str(), "member_%zu", &k) == 1 && k % size_t(opt.ranks) == size_t(opt.rank)) {
      std::error_code ec;
      std::filesystem::remove(entry.path(), ec);
    }
  }
  EnsembleProgress done;
  for (size_t k = size_t(opt.rank); k < opt.members; k += size_t(opt.ranks)) {
    if (member_done(opt, k)) {
      ++done.resumed;
      continue;
    }
    if (opt.progress) opt.progress("members", double(k) / double(opt.members));
    MeshOptions mo = opt.mesh;
    mo.seed = member_seed(opt.mesh.seed, k);
    mo.progress = nullptr;  // the ensemble's progress is by member
    RunReport run;
    PolyMesh mesh;
    // One member that cannot be meshed (froth's fault, or an r its sample cannot use) does not
    // stop the others: it is noted and reported, and the next run tries it again. I/O errors
    // still stop the run.
    try {
      mesh = generate_mesh(domain, mo, &run);
    } catch (const Error& e) {
      if (e.kind() == ErrorKind::Io) throw;
      const Json note = {{"index", k}, {"seed", mo.seed}, {"exit_code", e.exit_code()}, {"error", e.what()}};
      write_atomically(failure_note(opt, k), [&](std::ostream& out) { out << note.dump(2) << "\n"; });
      ++done.failed;
      continue;
    }
    std::error_code ec;
    std::filesystem::remove(failure_note(opt, k), ec);
    const auto t0 = std::chrono::steady_clock::now();
    const std::filesystem::path file = opt.dir / member_file(k);
    write_vtu(mesh, run, file);
    run.stages.push_back(
        {"writing", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), peak_rss_bytes()});
    // The sidecar last: its presence marks the member complete.
    const auto [size, crc] = crc_of(file);
    Json j = Json::parse(report_json_text(run));
    j["member"] = {{"index", k},          {"seed", mo.seed}, {"file", member_file(k)}, {"bytes", size},
                   {"crc32", crc},        {"input", opt.input}, {"quality", opt.mesh.quality}};
    const std::string text = j.dump(2) + "\n";
    write_atomically(sidecar(opt, k), [&](std::ostream& out) { out << text; });
    ++done.built;
  }
  return done;
}

std::vector<int> write_ensemble_summary(const Domain& domain, const EnsembleOptions& given,
                                        const EnsembleProgress& progress) {
  const EnsembleOptions opt = resolved(domain, given);
  std::vector<int> codes;
  std::vector<char> missing(opt.members, 0);
  Json members = Json::array();
  Spread cells, mean_volume, min_aspect, max_aspect, seconds;
  Json failed = Json::array();
  for (size_t k = 0; k < opt.members; ++k) {
    std::ifstream in(sidecar(opt, k));
    if (!in) {
      std::ifstream why(failure_note(opt, k));
      if (!why) fail(ErrorKind::Io, fmt::format("{}: missing: member {} was not built", sidecar(opt, k).string(), k));
      failed.push_back(Json::parse(why));
      codes.push_back(failed.back().value("exit_code", int(ErrorKind::Internal)));
      missing[k] = 1;
      continue;
    }
    const Json j = Json::parse(in);
    const double n = j["mesh"]["cells"].get<double>();
    Json m = {{"index", k},
              {"seed", j["member"]["seed"]},
              {"file", j["member"]["file"]},
              {"cells", j["mesh"]["cells"]},
              {"volume_relative_error", j["volume"]["relative_error"]},
              {"mean_cell_volume", j["volume"]["cells_sum"].get<double>() / n},
              {"seconds", j["seconds_total"]}};
    cells.v.push_back(n);
    mean_volume.v.push_back(j["volume"]["cells_sum"].get<double>() / n);
    seconds.v.push_back(j["seconds_total"].get<double>());
    if (j.contains("quality")) {
      double lo = INFINITY, hi = 0;
      for (const auto& [kind, q] : j["quality"]["cells"].items()) {
        // Null where a kind has no finite aspect ratio (quality-report.schema.json).
        if (q["aspect"]["min"].is_number()) lo = std::min(lo, q["aspect"]["min"].get<double>());
        if (q["aspect"]["max"].is_number()) hi = std::max(hi, q["aspect"]["max"].get<double>());
      }
      m["quality"] = {{"min_aspect", lo},
                      {"max_aspect", hi},
                      {"interior_aspect", j["quality"]["cells"].contains("interior")
                                              ? j["quality"]["cells"]["interior"]["aspect"]
                                              : Json()},
                      {"bounds", j.contains("quality_before_welding") ? j["quality_before_welding"]["bounds"]
                                                                      : j["quality"]["bounds"]}};
      min_aspect.v.push_back(lo);
      max_aspect.v.push_back(hi);
    }
    members.push_back(m);
  }
  Json out;
  out["command"] = opt.command;
  out["froth_version"] = FROTH_VERSION;
  out["input"] = {{"domain", opt.input}, {"r", opt.mesh.r}, {"seed", opt.mesh.seed}, {"members", opt.members},
                  {"weld", *opt.mesh.weld}, {"quality", opt.mesh.quality}, {"grade", opt.mesh.grade}};
  if (opt.mesh.grade) out["input"]["min_r"] = opt.mesh.min_r, out["input"]["max_grading"] = opt.mesh.grading;
  out["member_seeds"] = "Philox4x64-10 keyed by (seed, 2) at counter (k, 0, 0, 0), first word";
  out["this_run"] = {{"built", progress.built}, {"already_complete", progress.resumed}, {"failed", failed.size()}};
  out["failed_members"] = failed;
  out["members"] = members;
  out["spread"] = {{"cells", cells.json()},
                   {"mean_cell_volume", mean_volume.json()},
                   {"min_aspect", min_aspect.json()},
                   {"max_aspect", max_aspect.json()},
                   {"seconds", seconds.json()}};
  const std::string text = out.dump(2) + "\n";
  write_atomically(opt.dir / "ensemble.json", [&](std::ostream& o) { o << text; });
  write_atomically(opt.dir / "ensemble.pvd", [&](std::ostream& o) {
    o << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "<Collection>\n";
    for (size_t k = 0; k < opt.members; ++k)
      if (!missing[k])
        o << fmt::format("<DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", k, member_file(k));
    o << "</Collection>\n</VTKFile>\n";
  });
  return codes;
}

}  // namespace froth
