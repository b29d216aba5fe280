// The error every reader throws for bad input: names the file, the place and the problem.
// The Python bindings turn it into patina.errors.FormatError.
#pragma once

#include <stdexcept>
#include <string>

namespace patina {

struct FormatError : std::runtime_error {
    std::string path, where, problem;
    FormatError(std::string path_, std::string where_, std::string problem_)
        : std::runtime_error(path_ + (where_.empty() ? "" : " (" + where_ + ")") + ": " + problem_),
          path(std::move(path_)),
          where(std::move(where_)),
          problem(std::move(problem_)) {}
};

}  // namespace patina
