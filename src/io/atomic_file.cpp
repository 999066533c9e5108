#include "io/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdlib>
#include <atomic>
#include <cstring>
#include <mutex>

#include <fmt/format.h>

#include "froth/error.hpp"

namespace froth {

namespace {

// The temporary files being written and the folders made for them, for the signal handler:
// fixed slots of plain characters, each claimed and released atomically, since a handler may
// only read memory, unlink and rmdir.
constexpr size_t kSlots = 64, kPathBytes = 4096;
constexpr int kFreeSlot = 0, kFileSlot = 1, kFillingSlot = 2, kFolderSlot = 3;
std::array<std::array<char, kPathBytes>, kSlots> g_tmp_paths;
std::array<std::atomic<int>, kSlots> g_tmp_used{};

int register_temporary(const std::filesystem::path& tmp, int kind = kFileSlot) {
  const std::string s = tmp.string();
  if (s.size() >= kPathBytes) return -1;
  for (size_t k = 0; k < kSlots; ++k) {
    int expected = kFreeSlot;
    if (!g_tmp_used[k].compare_exchange_strong(expected, kFillingSlot)) continue;
    std::memcpy(g_tmp_paths[k].data(), s.c_str(), s.size() + 1);
    g_tmp_used[k].store(kind);
    return int(k);
  }
  return -1;
}

void release_temporary(int slot) {
  if (slot >= 0) g_tmp_used[size_t(slot)].store(0);
}

// Files first, then the folders made for them, deepest first: rmdir takes only an empty one, so
// passes repeat while one goes.
extern "C" void remove_temporaries_and_exit(int sig) {
  for (size_t k = 0; k < kSlots; ++k)
    if (g_tmp_used[k].load() == kFileSlot) ::unlink(g_tmp_paths[k].data());
  for (bool removed = true; removed;) {
    removed = false;
    for (size_t k = 0; k < kSlots; ++k)
      if (g_tmp_used[k].load() == kFolderSlot && ::rmdir(g_tmp_paths[k].data()) == 0)
        g_tmp_used[k].store(kFreeSlot), removed = true;
  }
  ::_exit(128 + sig);
}

thread_local OutputGroup* g_group = nullptr;

// Devices and pipes (e.g. /dev/null, /dev/stdout) are written in place: renaming a file over
// them would replace the device.
void write_in_place(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  std::ofstream out(path, std::ios::binary);
  if (!out) fail(ErrorKind::Io, fmt::format("{}: cannot open for writing", path.string()));
  write(out);
  out.flush();
  if (!out) fail(ErrorKind::Io, fmt::format("{}: write failed", path.string()));
}

void rename_into_place(const std::filesystem::path& tmp, const std::filesystem::path& path) {
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    fail(ErrorKind::Io, fmt::format("{}: cannot rename the finished file into place", path.string()));
  }
}

// The temporaries registered for the signal handler, by path.
std::mutex g_registered_mutex;
std::vector<std::pair<std::filesystem::path, int>>& registered() {
  static std::vector<std::pair<std::filesystem::path, int>> slots;
  return slots;
}

void remember(const std::filesystem::path& tmp, int kind = kFileSlot) {
  std::lock_guard<std::mutex> lock(g_registered_mutex);
  registered().push_back({tmp, register_temporary(tmp, kind)});
}

void forget(const std::filesystem::path& tmp) {
  std::lock_guard<std::mutex> lock(g_registered_mutex);
  auto& slots = registered();
  for (size_t k = 0; k < slots.size(); ++k)
    if (slots[k].first == tmp) {
      release_temporary(slots[k].second);
      slots.erase(slots.begin() + std::ptrdiff_t(k));
      return;
    }
}

// A temporary of `path` (NAME.tmpPID, or NAME.tmpPID.EXT) left by a process that no longer runs
// on this machine (SIGKILL, a power cut) is removed before the next run writes `path`.
void remove_stale_temporaries(const std::filesystem::path& path) {
  std::error_code ec;
  const std::string prefix = path.filename().string() + ".tmp";
  const std::filesystem::path folder = path.has_parent_path() ? path.parent_path() : ".";
  for (std::filesystem::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) continue;
    const size_t digits = name.find_first_not_of("0123456789", prefix.size());
    if (digits == prefix.size() || (digits != std::string::npos && name[digits] != '.')) continue;
    const long pid = std::strtol(name.c_str() + prefix.size(), nullptr, 10);
    if (pid == long(::getpid())) continue;  // this run's own
    if (pid <= 0 || (::kill(pid_t(pid), 0) != 0 && errno == ESRCH)) std::filesystem::remove(it->path(), ec);
  }
}

// A symbolic link stays a link: its target is what gets replaced.
std::filesystem::path link_target(const std::filesystem::path& requested) {
  std::error_code ec;
  if (!std::filesystem::is_symlink(requested, ec)) return requested;
  const std::filesystem::path target = std::filesystem::weakly_canonical(requested, ec);
  return ec ? requested : target;
}

}  // namespace

std::filesystem::path temporary_name(const std::filesystem::path& path, const std::string& extension) {
  remove_stale_temporaries(path);
  std::filesystem::path tmp = path;
  tmp += fmt::format(".tmp{}{}", ::getpid(), extension);
  return tmp;
}

void make_output_folder(const std::filesystem::path& folder) {
  std::error_code ec;
  std::vector<std::filesystem::path> missing;
  for (std::filesystem::path p = std::filesystem::absolute(folder, ec); !p.empty() && !std::filesystem::exists(p, ec);
       p = p.parent_path()) {
    missing.push_back(p);
    if (p == p.root_path()) break;
  }
  for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
    remember(*it, kFolderSlot);  // before it exists: a signal between the two must still find it
    if (!std::filesystem::create_directory(*it, ec) && ec) {
      forget(*it);
      fail(ErrorKind::Io, fmt::format("{}: cannot create the folder ({})", it->string(), ec.message()));
    }
    if (g_group) g_group->made_folder(*it);
    else forget(*it);  // (without a group the folder stays: a file is about to be renamed into it)
  }
}

void write_atomically(const std::filesystem::path& requested, const std::function<void(std::ostream&)>& write) {
  std::error_code ec;
  const std::filesystem::path path = link_target(requested);
  const auto status = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status) &&
      !std::filesystem::is_directory(status))
    return write_in_place(path, write);  // (a directory is refused below)
  write_atomically_by_name(path, [&](const std::filesystem::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) fail(ErrorKind::Io, fmt::format("{}: cannot write there ({})", path.string(), std::strerror(errno)));
    write(out);
    out.flush();
    if (!out) fail(ErrorKind::Io, fmt::format("{}: write failed (disk full?)", path.string()));
  });
}

void write_atomically_by_name(const std::filesystem::path& requested,
                              const std::function<void(const std::filesystem::path& tmp)>& write,
                              const std::string& extension) {
  std::error_code ec;
  const std::filesystem::path path = link_target(requested);
  if (std::filesystem::is_directory(path, ec))
    fail(ErrorKind::Io, fmt::format("{}: is a directory, not a file to write", path.string()));
  const std::filesystem::path tmp = temporary_name(path, extension);
  remember(tmp);
  try {
    write(tmp);
  } catch (...) {
    std::filesystem::remove(tmp, ec);
    forget(tmp);
    throw;
  }
  if (g_group) return g_group->defer(tmp, path);
  rename_into_place(tmp, path);
  forget(tmp);
}

OutputGroup::OutputGroup() : outer_(g_group) { g_group = this; }

OutputGroup::~OutputGroup() {
  g_group = outer_;
  std::error_code ec;
  for (const auto& [tmp, target] : pending_) {
    std::filesystem::remove(tmp, ec);
    forget(tmp);
  }
  for (auto it = folders_.rbegin(); it != folders_.rend(); ++it) {  // deepest first; only if empty
    std::filesystem::remove(*it, ec);
    forget(*it);
  }
}

void OutputGroup::made_folder(const std::filesystem::path& folder) { folders_.push_back(folder); }

void OutputGroup::defer(const std::filesystem::path& tmp, const std::filesystem::path& target) {
  pending_.push_back({tmp, target});
}

void OutputGroup::commit() {
  if (outer_) {  // a group within a group: its files appear with the outer group's
    for (const auto& [tmp, target] : pending_) outer_->defer(tmp, target);
    for (const auto& folder : folders_) outer_->made_folder(folder);
    pending_.clear(), folders_.clear();
    return;
  }
  for (const auto& [tmp, target] : pending_) {
    rename_into_place(tmp, target);
    forget(tmp);
  }
  for (const auto& folder : folders_) forget(folder);
  pending_.clear(), folders_.clear();
}

void remove_temporaries_on_signal() {
  struct sigaction sa {};
  sa.sa_handler = remove_temporaries_and_exit;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

}  // namespace froth
