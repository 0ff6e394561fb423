// The puff as Corvis sees it: the corneal sections and the run's scalars
// at the camera's frame rate, and the biomarkers taken from those frames.
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "biomarkers/biomarkers.h"
#include "biomarkers/section.h"

namespace nct::biomarkers
{

/// Named scalars of one instant, e.g. {"iop_mmHg", 15.2}.
using Columns = std::vector<std::pair<std::string, double>>;

/// The section at s in [0, 1] of a step from a to b, h [ms] long: each
/// node's position and axial displacement by the cubic Hermite interpolant
/// of its values and velocities at both ends (exact for cubics: O(h^4)
/// against the linear blend's O(h^2), which flattens the apex's peak by
/// about h^2 |u''| / 8), its velocity by the interpolant's derivative.
SectionState hermite(const SectionState& a, const SectionState& b, double s, double h);

/// Frames at times k / frame_rate from the start of the puff (t = 0),
/// interpolated between the solver's steps (which may be irregular): the
/// corneal sections by `hermite`, the state's scalars linearly.
/// Every rank holds the same record.
class Record
{
public:
  /// `frame_rate` [1/s]; the whole-eye motion is the axial displacement
  /// of the anterior surface at reference x = whole_eye_x [mm]; `known`
  /// are columns given as functions of time (e.g. the prescribed apex air
  /// pressure), evaluated at every step and frame instead of interpolated.
  Record(Section anterior, Section posterior, double frame_rate, double whole_eye_x,
         std::vector<std::pair<std::string, std::function<double(double)>>> known = {});

  /// The state after a step (or at the start) at time t [ms]: `state` is
  /// interpolated into the frames, `solver` only goes to the step table.
  /// Before t = 0 (the rest) only the step table grows. The apex
  /// displacement and whole-eye motion are taken from the first state
  /// added (the eye at rest). Collective.
  void add(double t, const Columns& state, const Columns& solver);

  /// One row per step: t_ms, the solver's, the known and the state's
  /// columns, the apex displacement and the whole-eye motion.
  std::string steps_csv() const;
  /// One row per frame: t_ms, the apex displacement, whole-eye motion, the
  /// known and the state's columns.
  std::string frames_csv() const;
  /// One row per node and frame: frame, t_ms, surface (anterior or
  /// posterior), x_mm, y_mm (the full section, mirrored).
  std::string profiles_csv() const;

  /// The biomarkers of the frames (see biomarkers::analyse), time in
  /// frames counted at the record's own frame rate.
  Result analyse(Definitions d) const;
  /// A known or state column at time t [ms] of the frames (linear in between).
  double at(const std::string& column, double t) const;
  /// The largest value of a known or state column over the frames.
  double max(const std::string& column) const;
  std::size_t frames() const { return _frames.size(); }
  /// The last step's apex displacement (frames.csv's apex_displacement_mm:
  /// axial, from the first state added) [mm].
  double last_apex() const { return _steps.back()[_steps.back().size() - 2]; }

  /// What has been recorded, for a checkpoint (the sections and the known
  /// columns are the constructor's); restore() takes it back.
  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

private:
  struct Instant
  {
    double t;
    SectionState anterior, posterior;
    std::vector<double> state; ///< the known and the state columns' values
  };
  std::vector<double> column(const std::string& name) const;
  /// Axial displacements from the first recorded state.
  double apex(const Instant& i) const { return i.anterior.uy.front() - _origin[0]; }
  double whole_eye(const Instant& i) const
  {
    return i.anterior.displacement_at(_whole_eye_x) - _origin[1];
  }

  Section _anterior, _posterior;
  double _frame_interval, _whole_eye_x;
  std::array<double, 2> _origin{}; ///< apex and whole-eye displacement at the first add()
  std::vector<std::pair<std::string, std::function<double(double)>>> _known;
  std::vector<std::string> _state_names, _solver_names; ///< state: known ones first
  std::vector<Instant> _frames;
  std::optional<Instant> _last; ///< the last step at t >= 0
  /// Per step: t, the solver's values, the state's, apex, whole-eye motion.
  std::vector<std::vector<double>> _steps;
};

} // namespace nct::biomarkers
