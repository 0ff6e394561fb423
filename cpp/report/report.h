// A folder's web page (python/nct/report): `nct report DIR`, and the page a
// run, a study, a fit or a cohort writes at its end.
#pragma once

#include <filesystem>

namespace nct::report
{

/// Write the page of a run, study, fit or cohort folder (DIR/report.html,
/// or `out`) by `python3 -m nct.report`: Debian's python3 with the source
/// tree's python/ on its path, its output on this process' streams.
/// Returns its exit code: 0 written, 2 not a folder nct wrote, 127 the
/// writer could not start.
int write(const std::filesystem::path& folder, const std::filesystem::path& out = {});

/// The page at the end of a run, study, fit or cohort: written, or a line
/// on stderr saying why not. Never changes the caller's outcome.
void after(const std::filesystem::path& folder);

} // namespace nct::report
