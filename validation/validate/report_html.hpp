#pragma once
// DIR/report.html: one page that opens from disk — the pass/fail table first, then per scene its
// description (the scene file's opening comment), its engines with their status and wall time, its
// comparisons (error, where, tolerance, share of the tolerance used), the λ_crit(a) table of a scan, the end
// of the log of a scene that did not pass, and every plot under DIR/<scene>/ (report.png: moments with the
// engines overlaid and ±2σ bands for ensembles, size distributions; final.png: aggregate pictures;
// phase_diagram.png of a scan; any other PNG, e.g. heat maps). Images are referenced by paths relative
// to DIR (the page is complete as long as DIR is kept together). All text is HTML-escaped.
#include <filesystem>
#include <string>
#include <vector>

#include "validation/validate/validation_json.hpp"

namespace aggkit {

std::string html_escape(const std::string& text);
// A relative path as a URL path: every byte other than A-Z a-z 0-9 - . _ ~ / percent-encoded.
std::string url_path(const std::string& relative);

std::string report_html(const std::filesystem::path& out, const std::vector<SceneOutcome>& scenes,
                        const ValidationTotals& totals);

}  // namespace aggkit
