#pragma once
// Figures are drawn by the Python module studies/python/mfdem (matplotlib and h5py from Debian)
// from numbers the C++ has written; a command calls it at its end through this.
#include <string>
#include <vector>

namespace mfdem::cli {

// Runs `PYTHON -m mfdem.MODULE ARGS...` with studies/python on PYTHONPATH, PYTHON being
// $MFDEM_PYTHON, else /usr/bin/python3 (Debian's, which has matplotlib), else python3 on PATH.
// Its output goes to this process's. Returns false, after a warning on stderr saying how to draw
// them later, when Python is missing or the module fails: figures never fail a finished study.
bool draw_figures(const std::string& module, const std::vector<std::string>& args);

// draw_figures(module, {out} + --quiet when quiet): a study's figures from the data in its folder.
bool draw_study_figures(const std::string& module, const std::string& out, bool quiet);

// The command a user can run to draw them again, for messages and results pages.
std::string figure_command(const std::string& module, const std::vector<std::string>& args);

}  // namespace mfdem::cli
