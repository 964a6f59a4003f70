// The browsable report of a run: one static HTML page (no scripts fetched from anywhere) with the
// summary and a table of cases. Every string that comes from a case is HTML-escaped.
#pragma once

#include <string>

#include "runner/run.h"

namespace hdrc {

std::string html_escape(const std::string& s);
std::string html_report(const RunReport& r);

}  // namespace hdrc
