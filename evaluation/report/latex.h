// Text for LaTeX tables (eval.tex, the matrix's table.tex).
#pragma once

#include <string>

namespace mavloc {

// Escapes the characters LaTeX treats specially in running text: _ % & # $ { } with a backslash,
// \ ~ ^ as \textbackslash{}, \textasciitilde{}, \textasciicircum{}.
std::string LatexEscape(const std::string& text);

}  // namespace mavloc
