#include "io/text.h"

#include <fstream>
#include <sstream>

namespace nct::io
{

std::string read_text(const std::filesystem::path& file)
{
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

} // namespace nct::io
