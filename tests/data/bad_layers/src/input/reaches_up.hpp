#pragma once
// A deliberate layering violation: the input layer reaching up into the command line.
#include "src/cli/run_command.hpp"
