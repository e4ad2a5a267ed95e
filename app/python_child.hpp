// python_child.hpp — how the program starts its Python parts (a sweep's protocol runs,
// `cdpowder stress-bounds`): which interpreter, and where the package of a build tree is.
#pragma once

#include <string>

namespace cdpowder::app {

/// The variable that names the interpreter.
inline constexpr const char* kPythonVariable = "CDPOWDER_PYTHON";

/// The Python that runs the package: $CDPOWDER_PYTHON, or python3 on PATH.
[[nodiscard]] std::string python_interpreter();

/// The folder that holds the package cdpowder beside this program in a build tree
/// (build/…/app/cdpowder and build/…/python/cdpowder), or "" for an installed program, whose
/// package is where its prefix's Python finds it.
[[nodiscard]] std::string package_folder_of_build();

/// PYTHONPATH for a Python child: the build tree's package first, then this process's
/// PYTHONPATH; "" for an installed program (the child keeps this process's PYTHONPATH).
[[nodiscard]] std::string python_path_for_child();

}  // namespace cdpowder::app
