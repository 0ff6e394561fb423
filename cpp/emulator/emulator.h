// An emulator of the model: Gaussian processes trained by
// python/nct/emulator.py (scikit-learn) and evaluated here from the file
// it exports, to the library's own predictions:
//
//   mean = y_mean + y_std k*^T alpha,
//   var  = y_std^2 (c + noise - |L^-1 k*|^2),
//   k*_i = c (1 + sqrt5 r + 5 r^2 / 3) exp(-sqrt5 r),  r = |(u - X_i) / l|,
//
// u the inputs on the unit cube (a log-scale input through its logarithm).
// The curves (apex, whole eye, profiles) are the mean plus an SVD basis
// times the components' GPs, in units of the device's noise; what the
// dropped components held is a variance per output (Higdon et al. 2008).
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace nct::emulator
{

/// One Gaussian process of the file.
struct Process
{
  std::vector<std::vector<double>> X; ///< training inputs on the unit cube
  std::vector<double> alpha;          ///< K^-1 (y - mean) / std
  std::vector<std::vector<double>> L; ///< K's lower Cholesky factor
  double constant = 1, noise = 0, y_mean = 0, y_std = 1;
  std::vector<double> length_scale;   ///< per input
};

/// A value's mean, variance and their gradients with respect to the
/// inputs (natural units).
struct Value
{
  double mean = 0, variance = 0;
  std::vector<double> gradient, variance_gradient;
};

/// An input's range and scale, and the scene keys it sets.
struct Input
{
  std::string name;
  double low, high;
  bool log;
  std::vector<std::string> keys;
};

/// A linear functional of the curves' outputs: (output index, weight) pairs
/// (an interpolation between frames, say).
using Functional = std::vector<std::pair<std::size_t, double>>;

/// Linear functionals of the curves, their fixed part: at a point x each
/// is offset + factor w(x), w the components' weights, with covariance
/// factor diag(var w) factor^T + diag(truncation).
struct Projection
{
  std::vector<double> offset;              ///< per functional [mm]
  std::vector<std::vector<double>> factor; ///< per functional, per component [mm]
  std::vector<double> truncation;          ///< per functional [mm^2]
};

/// An exported emulator (python/nct/emulator.py, format "nct-emulator-1").
class Emulator
{
public:
  /// Read the file; throws std::invalid_argument naming it and what is wrong.
  explicit Emulator(const std::filesystem::path& file);

  /// The inputs, in order.
  const std::vector<Input>& inputs() const { return _inputs; }

  /// The curves' outputs (apex, whole eye, profiles, one after the
  /// other), in mm and mm^2, and their gradients; throws
  /// std::out_of_range naming an input outside the box.
  std::vector<Value> curves(const std::vector<double>& x) const;

  /// Linear functionals of the curves' outputs (their fixed part).
  Projection project(const std::vector<Functional>& functionals) const;

  /// The curves' components kept.
  std::size_t component_count() const { return _components.size(); }

  /// The components' weights at x: mean, variance and, with
  /// `derivatives`, their gradients; throws std::out_of_range as curves().
  std::vector<Value> components(const std::vector<double>& x, bool derivatives = true) const;

  /// A reading's value (its key in summary.json; the gradients zero
  /// without `derivatives`); throws std::out_of_range for an input outside
  /// the box or a reading the emulator lacks.
  Value reading(const std::string& key, const std::vector<double>& x,
                bool derivatives = true) const;

  /// The readings the emulator holds.
  std::vector<std::string> readings() const;

  /// The range a reading spanned over the training runs.
  std::pair<double, double> reading_range(const std::string& key) const;

  /// Throws std::out_of_range naming the first input of x outside the box.
  void check_inside(const std::vector<double>& x) const { unit(x); }

  /// The curves' blocks and their sizes, in order.
  const std::vector<std::pair<std::string, std::size_t>>& blocks() const { return _blocks; }

  /// The curves' frame clock [ms]; the profiles' frames [ms] and places [mm]
  /// (the profiles block: per frame, per place).
  const std::vector<double>& t_ms() const { return _t_ms; }
  const std::vector<double>& profile_t_ms() const { return _profile_t_ms; }
  const std::vector<double>& profile_x_mm() const { return _profile_x_mm; }

private:
  /// x on the unit cube, and d(unit)/dx per input.
  std::pair<std::vector<double>, std::vector<double>> unit(const std::vector<double>& x) const;

  std::vector<Input> _inputs;
  double _noise_mm = 0.02;
  std::vector<std::pair<std::string, std::size_t>> _blocks;
  std::vector<double> _t_ms, _profile_t_ms, _profile_x_mm;
  std::vector<double> _mean, _truncation;
  std::vector<std::vector<double>> _basis; ///< (outputs, components)
  std::vector<Process> _components;
  std::map<std::string, Process> _readings;
  std::map<std::string, std::pair<double, double>> _reading_ranges;
};

} // namespace nct::emulator
