// What a fit's forward run reads at the observation points: summary.json's
// biomarkers, frames.csv's curves and profiles.csv's corneal profiles,
// interpolated at the measured times and positions.
#pragma once

#include <filesystem>
#include <vector>

#include "fit/fit.h"

namespace nct::fit
{

/// The model's value at each observation point (in the order of
/// fit.observations and their points) of the converged run in folder
/// `run`; throws scene::Error when an observation lies outside what it
/// computed.
std::vector<double> model_values(const Fit& fit, const std::filesystem::path& run);

} // namespace nct::fit
