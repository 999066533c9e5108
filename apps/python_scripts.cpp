#include "python_scripts.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include <fmt/format.h>

#include "froth/error.hpp"

namespace froth_cli {

std::string script_path(const std::string& name) {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "froth" / name;
    if (std::filesystem::exists(installed, ec)) return installed.string();
  }
  const std::filesystem::path source = std::filesystem::path(FROTH_SCRIPTS_DIR) / name;
  if (std::filesystem::exists(source, ec)) return source.string();
  froth::fail(froth::ErrorKind::Io, fmt::format("cannot find froth's script {} (neither {} nor {} exists; reinstall froth)",
                                                name, (exe.parent_path().parent_path() / "share/froth").string(),
                                                FROTH_SCRIPTS_DIR));
}

void run_python_script(const std::string& name, const std::vector<std::string>& args, bool needs_display,
                       const std::string& what) {
  const std::string script = script_path(name);
  const char* display = std::getenv("DISPLAY");
  const bool virtual_display = needs_display && (display == nullptr || *display == '\0');
  std::vector<std::string> argv;
  if (virtual_display) argv = {"/usr/bin/xvfb-run", "-a", "-s", "-screen 0 1920x1200x24"};
  argv.push_back("/usr/bin/python3");
  argv.push_back(script);
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> c_argv;
  for (std::string& a : argv) c_argv.push_back(a.data());
  c_argv.push_back(nullptr);
  const pid_t pid = fork();
  if (pid == 0) {
    execv(c_argv[0], c_argv.data());
    _exit(127);
  }
  int status = 0;
  const bool waited = pid > 0 && waitpid(pid, &status, 0) == pid;
  const int code = waited && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  // Exit status 2: the script refused its arguments (its message is above), a usage error.
  if (code == 2) froth::fail(froth::ErrorKind::Usage, fmt::format("could not {}: the arguments were refused (above)", what));
  if (code != 0)
    froth::fail(froth::ErrorKind::Io,
                fmt::format("could not {} ({} with /usr/bin/python3{}; exit status {})", what, script,
                            virtual_display ? " under /usr/bin/xvfb-run (Debian xvfb and xauth)" : "", code));
}

}  // namespace froth_cli
