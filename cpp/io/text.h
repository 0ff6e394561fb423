// A text file read whole.
#pragma once

#include <filesystem>
#include <string>

namespace nct::io
{

/// The whole text of a file ("" when it cannot be read).
std::string read_text(const std::filesystem::path& file);

} // namespace nct::io
