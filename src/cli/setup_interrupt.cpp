#include "src/cli/setup_interrupt.hpp"

#include <unistd.h>

#include <csignal>
#include <cstring>

namespace ckpd {

namespace {

extern "C" void stop_during_setup(int signal) {
  const char* text =
      signal == SIGINT ? "ckpd: interrupted (SIGINT) during set-up; nothing was run or written\n"
                       : "ckpd: interrupted (SIGTERM) during set-up; nothing was run or written\n";
  const ssize_t ignored = write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
  _exit(130);
}

}  // namespace

void stop_on_signal_during_setup() {
  std::signal(SIGINT, stop_during_setup);
  std::signal(SIGTERM, stop_during_setup);
}

}  // namespace ckpd
