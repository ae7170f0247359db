// Starts the `inhap` program built alongside the tests as a child process (for tests that need
// to kill it, or run two programs at once), its output going to a file.
#pragma once

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <sstream>
#include <string>
#include <vector>

namespace inhap::test {

class Child {
 public:
  /// `args`: whitespace-separated arguments (no quoting); output (stdout and stderr) to `log`.
  Child(const std::string& args, const std::string& log) {
    std::vector<std::string> words{INHAP_CLI};
    std::istringstream in(args);
    for (std::string w; in >> w;) words.push_back(w);
    pid_ = ::fork();
    if (pid_ == 0) {
      const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) {
        ::dup2(fd, 1);
        ::dup2(fd, 2);
      }
      std::vector<char*> argv;
      for (auto& w : words) argv.push_back(w.data());
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
  }
  ~Child() {
    if (pid_ > 0 && !waited_) {
      ::kill(pid_, SIGKILL);
      wait();
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  void kill(int sig = SIGKILL) { ::kill(pid_, sig); }
  /// Waits for the child; its exit code, or -1 when a signal ended it.
  int wait() {
    int st = 0;
    ::waitpid(pid_, &st, 0);
    waited_ = true;
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  }

 private:
  pid_t pid_ = -1;
  bool waited_ = false;
};

}  // namespace inhap::test
