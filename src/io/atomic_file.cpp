#include "io/atomic_file.hpp"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <atomic>
#include <cstring>
#include <mutex>

#include <fmt/format.h>

#include "froth/error.hpp"

namespace froth {

namespace {

// The temporary files being written, for the signal handler: fixed slots of plain characters,
// each claimed and released atomically, since a handler may only read memory and unlink.
constexpr size_t kSlots = 64, kPathBytes = 4096;
std::array<std::array<char, kPathBytes>, kSlots> g_tmp_paths;
std::array<std::atomic<int>, kSlots> g_tmp_used{};

int register_temporary(const std::filesystem::path& tmp) {
  const std::string s = tmp.string();
  if (s.size() >= kPathBytes) return -1;
  for (size_t k = 0; k < kSlots; ++k) {
    int expected = 0;
    if (!g_tmp_used[k].compare_exchange_strong(expected, 2)) continue;  // 2: being filled in
    std::memcpy(g_tmp_paths[k].data(), s.c_str(), s.size() + 1);
    g_tmp_used[k].store(1);
    return int(k);
  }
  return -1;
}

void release_temporary(int slot) {
  if (slot >= 0) g_tmp_used[size_t(slot)].store(0);
}

extern "C" void remove_temporaries_and_exit(int sig) {
  for (size_t k = 0; k < kSlots; ++k)
    if (g_tmp_used[k].load() == 1) ::unlink(g_tmp_paths[k].data());
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

void remember(const std::filesystem::path& tmp) {
  std::lock_guard<std::mutex> lock(g_registered_mutex);
  registered().push_back({tmp, register_temporary(tmp)});
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

}  // namespace

void write_atomically(const std::filesystem::path& requested, const std::function<void(std::ostream&)>& write) {
  std::error_code ec;
  // A symbolic link stays a link: its target is what gets replaced.
  std::filesystem::path path = std::filesystem::is_symlink(requested, ec) ? std::filesystem::canonical(requested, ec)
                                                                          : requested;
  if (ec) path = requested;
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

void write_atomically_by_name(const std::filesystem::path& path,
                              const std::function<void(const std::filesystem::path& tmp)>& write) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    fail(ErrorKind::Io, fmt::format("{}: is a directory, not a file to write", path.string()));
  std::filesystem::path tmp = path;
  tmp += fmt::format(".tmp{}", ::getpid());
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
}

void OutputGroup::defer(const std::filesystem::path& tmp, const std::filesystem::path& target) {
  pending_.push_back({tmp, target});
}

void OutputGroup::commit() {
  for (const auto& [tmp, target] : pending_) {
    rename_into_place(tmp, target);
    forget(tmp);
  }
  pending_.clear();
}

void remove_temporaries_on_signal() {
  struct sigaction sa {};
  sa.sa_handler = remove_temporaries_and_exit;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

}  // namespace froth
