// Runs the `tricell` program (or any program) as a shell command and captures what it did: the
// tests of the command as a program (cli_test, cli_large_test) go through this one runner.
#pragma once

#include <cstdlib>
#include <string>

#include <sys/wait.h>

#include "io/support/fixtures.hpp"

namespace tricell::test {

/// What a command run by run_command() did: its exit status (128 + signal when killed) and its
/// standard output and error.
struct CommandResult {
    int status = -1;
    std::string out;
    std::string err;
};

/// Runs `program args` in `directory`, its output and error captured through files in
/// `scratch` (a shell command line: args are quoted by the caller).
inline CommandResult run_command(const std::string& program, const std::string& args,
                                 const std::string& directory, const std::string& scratch) {
    const std::string out = scratch + "/stdout";
    const std::string err = scratch + "/stderr";
    const std::string command =
        "cd '" + directory + "' && '" + program + "' " + args + " > '" + out + "' 2> '" + err + "'";
    const int status = std::system(command.c_str());
    CommandResult result;
    result.status = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    result.out = read_text(out);
    result.err = read_text(err);
    return result;
}

} // namespace tricell::test
