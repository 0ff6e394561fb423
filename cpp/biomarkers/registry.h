// The values of a run's summary.json that studies compare and fits take as
// readings, each declared once with its unit and meaning: the puff's
// biomarkers and DCR parameters (docs/physics.md section 9), the cavities'
// largest pressures, the solver's counts and the wall time. The phases
// write them by these keys, studies and fits accept these keys, and
// `nct describe --biomarkers` exports them (python/nct/biomarkers.json).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

namespace nct::biomarkers
{

/// One value of summary.json.
struct Entry
{
  std::string key;     ///< the summary.json key; "<cavity>" stands for a cavity's name
  std::string unit;    ///< "" for a number without one
  std::string meaning;
  bool reading;        ///< a measurement of the puff (a fit may compare it), else a run's figure
};

/// Every entry, the readings before the run's figures.
const std::vector<Entry>& registry();

/// The entry of `key` ("<cavity>" matching cavity, aqueous or vitreous),
/// or null.
const Entry* find(std::string_view key);

/// summary[key] = value for a key of the registry; a key it lacks is a
/// programming error (std::logic_error).
void put(nlohmann::json& summary, std::string_view key, double value);

/// The registry as JSON (an array of {key, unit, meaning, reading}) or as
/// a Markdown table.
std::string describe(bool markdown);

} // namespace nct::biomarkers
