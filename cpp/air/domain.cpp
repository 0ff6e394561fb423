#include "air/domain.h"
#include "meshio/gmsh_options.h"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace nct::air
{
namespace
{

using Vec3 = std::array<double, 3>;

[[noreturn]] void reject(const std::string& key, double value, const std::string& accepted)
{
  std::ostringstream message;
  message << key << " = " << value << " is impossible: " << accepted;
  throw std::invalid_argument(message.str());
}

/// The eye's outer boundary curves: node tags of its anterior surfaces'
/// rim on z = 0 and on x = 0 (apex first) and on the cut plane (from
/// z = 0 to x = 0), with every node's coordinates.
struct Rim
{
  std::vector<std::size_t> on_z, on_x, ring;
  std::map<std::size_t, Vec3> x;
};

Rim eye_rim(double bottom_y)
{
  Rim rim;
  std::vector<std::size_t> tags;
  std::vector<double> xyz, uvw;
  gmsh::model::mesh::getNodes(tags, xyz, uvw, -1, -1, false, false);
  std::map<std::size_t, Vec3> all;
  for (std::size_t i = 0; i < tags.size(); ++i)
    all[tags[i]] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  // Rim edges belong to one anterior triangle only.
  std::map<std::pair<std::size_t, std::size_t>, int> edges;
  for (int surface : {1, 2}) // anterior_cornea, anterior_sclera (eye/geometry.h)
  {
    std::vector<std::size_t> elements, nodes;
    gmsh::model::mesh::getElementsByType(2, elements, nodes, surface);
    for (std::size_t t = 0; t < nodes.size(); t += 3)
      for (int k = 0; k < 3; ++k)
      {
        auto a = nodes[t + k], b = nodes[t + (k + 1) % 3];
        ++edges[{std::min(a, b), std::max(a, b)}];
      }
  }
  std::vector<std::size_t> boundary;
  for (auto& [e, count] : edges)
    if (count == 1)
      boundary.insert(boundary.end(), {e.first, e.second});
  std::sort(boundary.begin(), boundary.end());
  boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
  const double tol = 1e-9 * (1 + std::abs(bottom_y));
  for (std::size_t n : boundary)
  {
    const Vec3& p = all.at(n);
    rim.x[n] = p;
    if (std::abs(p[2]) < tol)
      rim.on_z.push_back(n);
    if (std::abs(p[0]) < tol)
      rim.on_x.push_back(n);
    if (std::abs(p[1] - bottom_y) < 1e-7 * (1 + std::abs(bottom_y)))
      rim.ring.push_back(n);
  }
  // The meridian profiles descend monotonically from the apex to the cut.
  auto by_height = [&](std::size_t a, std::size_t b) { return rim.x[a][1] > rim.x[b][1]; };
  std::sort(rim.on_z.begin(), rim.on_z.end(), by_height);
  std::sort(rim.on_x.begin(), rim.on_x.end(), by_height);
  std::sort(rim.ring.begin(), rim.ring.end(), [&](std::size_t a, std::size_t b) {
    return std::atan2(rim.x[a][2], rim.x[a][0]) < std::atan2(rim.x[b][2], rim.x[b][0]);
  });
  if (rim.on_z.size() < 2 || rim.on_x.size() < 2 || rim.ring.size() < 2
      || rim.on_z.front() != rim.on_x.front() || rim.on_z.back() != rim.ring.front()
      || rim.on_x.back() != rim.ring.back())
    throw std::runtime_error("nct::air::build: the eye's anterior rim is not two meridians "
                             "and a ring on the cut plane");
  return rim;
}

/// Mesh the current model in `dim` dimensions with the element size
/// `size(x, y, z)` alone (not from points, curvature or the boundary),
/// optionally optimised; the options and the size callback are restored
/// and removed afterwards.
void generate(int dim, const std::function<double(double, double, double)>& size, bool optimize)
{
  meshio::OptionGuard options;
  options.set("Mesh.MeshSizeFromPoints", 0);
  options.set("Mesh.MeshSizeFromCurvature", 0);
  options.set("Mesh.MeshSizeExtendFromBoundary", 0);
  if (optimize)
    options.set("Mesh.Optimize", 1);
  gmsh::model::mesh::setSizeCallback(
      [&size](int, int, double x, double y, double z) { return size(x, y, z); });
  struct RemoveCallback
  {
    ~RemoveCallback() { gmsh::model::mesh::removeSizeCallback(); }
  } remove_callback;
  gmsh::model::mesh::generate(dim);
}

/// The current (temporary) model's meshed nodes by tag; `eye` gets, per
/// geo point placed on an eye node (`eye_point`), that node for the mesh
/// node on the point.
std::map<std::size_t, Vec3> meshed_nodes(const std::map<int, std::size_t>& eye_point,
                                         std::map<std::size_t, std::size_t>& eye)
{
  std::vector<std::size_t> tags;
  std::vector<double> xyz, uvw;
  gmsh::model::mesh::getNodes(tags, xyz, uvw, -1, -1, true, false);
  std::map<std::size_t, Vec3> all;
  for (std::size_t i = 0; i < tags.size(); ++i)
    all[tags[i]] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  for (auto [point, node] : eye_point)
  {
    gmsh::model::mesh::getNodes(tags, xyz, uvw, 0, point, false, false);
    eye[tags.at(0)] = node;
  }
  return all;
}

/// Triangles and nodes of the meshed air boundary, in the temporary model.
struct Surfaces
{
  std::vector<std::pair<int, std::vector<std::size_t>>> triangles; ///< (group, nodes) per surface
  std::map<std::size_t, Vec3> x;          ///< every node used
  std::map<std::size_t, std::size_t> eye; ///< node -> the eye's node at its place
};

/// Build and mesh the air's boundary surfaces (not the eye's) in a
/// temporary gmsh model with the geo kernel; the eye's rim enters as
/// polylines through its nodes, one mesh edge per segment.
Surfaces mesh_boundary(const Domain& d, double apex_y, double bottom_y, const Rim* rim,
                       const std::function<double(double, double, double)>& size)
{
  namespace geo = gmsh::model::geo;
  const meshio::TemporaryModel boundary_model("air_boundary");

  const double y_exit = apex_y + d.nozzle_distance, y_top = y_exit + d.nozzle_length;
  const double rn = d.nozzle_diameter / 2, ro = d.nozzle_outer_diameter / 2, R = d.radius;
  const int centre_top = geo::addPoint(0, y_top, 0), centre_exit = geo::addPoint(0, y_exit, 0),
            centre_bottom = geo::addPoint(0, bottom_y, 0);

  // The eye's rim as polylines; eye_point maps geo points to eye nodes.
  std::map<std::size_t, int> point_of;
  std::map<int, std::size_t> eye_point;
  auto rim_point = [&](std::size_t n) {
    auto [it, fresh] = point_of.emplace(n, 0);
    if (fresh)
    {
      const Vec3& p = rim->x.at(n);
      it->second = geo::addPoint(p[0], p[1], p[2]);
      eye_point[it->second] = n;
    }
    return it->second;
  };
  auto polyline = [&](const std::vector<std::size_t>& nodes) {
    std::vector<int> lines;
    for (std::size_t i = 0; i + 1 < nodes.size(); ++i)
    {
      lines.push_back(geo::addLine(rim_point(nodes[i]), rim_point(nodes[i + 1])));
      geo::mesh::setTransfiniteCurve(lines.back(), 2);
    }
    return lines;
  };
  std::vector<int> profile_z, profile_x, ring;
  if (rim)
  {
    profile_z = polyline(rim->on_z);
    profile_x = polyline(rim->on_x);
    ring = polyline(rim->ring);
  }
  const int axis_start = rim ? rim_point(rim->on_z.front()) : centre_bottom;
  const int axis = geo::addLine(axis_start, centre_top);

  // One side per symmetry plane: point at (r, y) in the plane z = 0
  // (side 0) or x = 0 (side 1).
  auto side_point = [](int side, double r, double y) {
    return side == 0 ? geo::addPoint(r, y, 0) : geo::addPoint(0, y, r);
  };
  struct Side
  {
    // Points: the bore at the top and at the exit, the outer wall at the
    // exit and the top, the far cylinder at the top and the bottom.
    int bore_top = 0, bore_exit = 0, outer_exit = 0, outer_top = 0, far_top = 0, far_bottom = 0;
    // Lines, in order round the plane's outline from the axis' top.
    int inlet = 0, bore = 0, exit = 0, outer = 0, top = 0, lateral = 0, bottom = 0;
  };
  std::array<Side, 2> side;
  for (int s = 0; s < 2; ++s)
  {
    Side& c = side[s];
    c.bore_top = side_point(s, rn, y_top);
    c.bore_exit = side_point(s, rn, y_exit);
    c.outer_exit = side_point(s, ro, y_exit);
    c.outer_top = side_point(s, ro, y_top);
    c.far_top = side_point(s, R, y_top);
    c.far_bottom = side_point(s, R, bottom_y);
    const int ring_end = rim ? rim_point(s == 0 ? rim->ring.front() : rim->ring.back())
                             : centre_bottom;
    c.inlet = geo::addLine(centre_top, c.bore_top);
    c.bore = geo::addLine(c.bore_top, c.bore_exit);
    c.exit = geo::addLine(c.bore_exit, c.outer_exit);
    c.outer = geo::addLine(c.outer_exit, c.outer_top);
    c.top = geo::addLine(c.outer_top, c.far_top);
    c.lateral = geo::addLine(c.far_top, c.far_bottom);
    c.bottom = geo::addLine(c.far_bottom, ring_end);
  }
  // Arcs about the axis from side 0 to side 1.
  auto arc = [&](int Side::*point, int centre) {
    return geo::addCircleArc(side[0].*point, centre, side[1].*point);
  };
  const int arc_bore_top = arc(&Side::bore_top, centre_top);
  const int arc_bore_exit = arc(&Side::bore_exit, centre_exit);
  const int arc_outer_exit = arc(&Side::outer_exit, centre_exit);
  const int arc_outer_top = arc(&Side::outer_top, centre_top);
  const int arc_far_top = arc(&Side::far_top, centre_top);
  const int arc_far_bottom = arc(&Side::far_bottom, centre_bottom);

  auto plane = [](std::vector<int> loop) { return geo::addPlaneSurface({geo::addCurveLoop(loop)}); };
  auto patch = [](std::vector<int> loop) { return geo::addSurfaceFilling({geo::addCurveLoop(loop)}); };
  const Side &a = side[0], &b = side[1];
  std::vector<std::pair<int, int>> surfaces; // (group, geo surface)
  auto add = [&](Group g, int s) { surfaces.emplace_back(static_cast<int>(g), s); };
  add(Group::inlet, plane({a.inlet, arc_bore_top, -b.inlet}));
  add(Group::nozzle, patch({a.bore, arc_bore_exit, -b.bore, -arc_bore_top}));
  add(Group::nozzle, plane({a.exit, arc_outer_exit, -b.exit, -arc_bore_exit}));
  add(Group::nozzle, patch({a.outer, arc_outer_top, -b.outer, -arc_outer_exit}));
  add(Group::outlet, plane({a.top, arc_far_top, -b.top, -arc_outer_top}));
  add(Group::outlet, patch({a.lateral, arc_far_bottom, -b.lateral, -arc_far_top}));
  std::vector<int> bottom{a.bottom};
  bottom.insert(bottom.end(), ring.begin(), ring.end());
  bottom.insert(bottom.end(), {-b.bottom, -arc_far_bottom});
  add(Group::outlet, plane(bottom));
  for (int s = 0; s < 2; ++s)
  {
    const Side& c = side[s];
    std::vector<int> loop{axis, c.inlet, c.bore, c.exit, c.outer, c.top, c.lateral, c.bottom};
    const std::vector<int>& profile = s == 0 ? profile_z : profile_x;
    for (auto it = profile.rbegin(); it != profile.rend(); ++it)
      loop.push_back(-*it);
    add(s == 0 ? Group::symmetry_z : Group::symmetry_x, plane(loop));
  }
  geo::synchronize();

  generate(2, size, false);

  Surfaces out;
  const std::map<std::size_t, Vec3> all = meshed_nodes(eye_point, out.eye);
  for (auto [group, s] : surfaces)
  {
    std::vector<std::size_t> elements, nodes;
    gmsh::model::mesh::getElementsByType(2, elements, nodes, s);
    for (std::size_t n : nodes)
      out.x[n] = all.at(n);
    out.triangles.emplace_back(group, std::move(nodes));
  }
  return out;
}

/// The eye section's anterior profile (curves 1 and 2: anterior_cornea,
/// anterior_sclera, eye/geometry.h), its node tags from the apex down to
/// the cut, with every node's coordinates.
std::pair<std::vector<std::size_t>, std::map<std::size_t, Vec3>> eye_profile()
{
  std::vector<std::size_t> tags;
  std::vector<double> xyz, uvw;
  gmsh::model::mesh::getNodes(tags, xyz, uvw, -1, -1, false, false);
  std::map<std::size_t, Vec3> all;
  for (std::size_t i = 0; i < tags.size(); ++i)
    all[tags[i]] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  std::vector<std::size_t> profile;
  for (int curve : {1, 2})
  {
    std::vector<std::size_t> elements, nodes;
    gmsh::model::mesh::getElementsByType(1, elements, nodes, curve);
    profile.insert(profile.end(), nodes.begin(), nodes.end());
  }
  std::sort(profile.begin(), profile.end());
  profile.erase(std::unique(profile.begin(), profile.end()), profile.end());
  // The meridian profile descends monotonically from the apex to the cut.
  std::sort(profile.begin(), profile.end(),
            [&](std::size_t a, std::size_t b) { return all.at(a)[1] > all.at(b)[1]; });
  std::map<std::size_t, Vec3> x;
  for (std::size_t n : profile)
    x[n] = all.at(n);
  if (profile.size() < 2 || std::abs(x.at(profile.front())[0]) > 1e-12)
    throw std::runtime_error("nct::air::build_section: the eye's anterior profile does not "
                             "start on the axis");
  return {profile, x};
}

/// The meshed air section: triangles, boundary segments by group (node
/// pairs), the nodes used and which of them are the eye's.
struct Section
{
  std::vector<std::size_t> triangles;
  std::map<int, std::vector<std::size_t>> segments;
  std::map<std::size_t, Vec3> x;
  std::map<std::size_t, std::size_t> eye; ///< node -> the eye's node at its place
};

/// Mesh the air's meridian section in a temporary gmsh model with the
/// geo kernel: the outline of the 3D builder's plane z = 0 (mesh_boundary),
/// the eye's profile (apex first) a polyline through its nodes, one mesh
/// edge per segment.
Section mesh_section(const Domain& d, double apex_y, double bottom_y,
                     const std::vector<std::size_t>* profile,
                     const std::map<std::size_t, Vec3>* profile_x,
                     const std::function<double(double, double, double)>& size)
{
  namespace geo = gmsh::model::geo;
  const meshio::TemporaryModel section_model("air_section");
  const double y_exit = apex_y + d.nozzle_distance, y_top = y_exit + d.nozzle_length;
  const double rn = d.nozzle_diameter / 2, ro = d.nozzle_outer_diameter / 2, R = d.radius;
  std::map<int, std::size_t> eye_point;
  std::vector<int> points;
  if (profile)
    for (std::size_t n : *profile)
    {
      const Vec3& p = profile_x->at(n);
      points.push_back(geo::addPoint(p[0], p[1], 0));
      eye_point[points.back()] = n;
    }
  const int apex = profile ? points.front() : geo::addPoint(0, bottom_y, 0);
  const int ring = profile ? points.back() : apex;
  const int centre_top = geo::addPoint(0, y_top, 0), bore_top = geo::addPoint(rn, y_top, 0),
            bore_exit = geo::addPoint(rn, y_exit, 0), outer_exit = geo::addPoint(ro, y_exit, 0),
            outer_top = geo::addPoint(ro, y_top, 0), far_top = geo::addPoint(R, y_top, 0),
            far_bottom = geo::addPoint(R, bottom_y, 0);
  std::vector<std::pair<int, int>> lines; // (group, line) round the outline
  auto line = [&](Group g, int a, int b) { lines.emplace_back(static_cast<int>(g), geo::addLine(a, b)); };
  line(Group::axis, apex, centre_top);
  line(Group::inlet, centre_top, bore_top);
  line(Group::nozzle, bore_top, bore_exit);
  line(Group::nozzle, bore_exit, outer_exit);
  line(Group::nozzle, outer_exit, outer_top);
  line(Group::outlet, outer_top, far_top);
  line(Group::outlet, far_top, far_bottom);
  line(Group::outlet, far_bottom, ring);
  std::vector<int> loop;
  for (auto [g, l] : lines)
    loop.push_back(l);
  for (std::size_t i = points.size(); i-- > 1;)
  {
    const int l = geo::addLine(points[i], points[i - 1]);
    geo::mesh::setTransfiniteCurve(l, 2);
    loop.push_back(l);
  }
  const int surface = geo::addPlaneSurface({geo::addCurveLoop(loop)});
  geo::synchronize();

  generate(2, size, true);

  Section out;
  const std::map<std::size_t, Vec3> all = meshed_nodes(eye_point, out.eye);
  std::vector<std::size_t> elements;
  gmsh::model::mesh::getElementsByType(2, elements, out.triangles, surface);
  for (std::size_t n : out.triangles)
    out.x[n] = all.at(n);
  for (auto [g, l] : lines)
  {
    // Fresh vectors: gmsh 4.8 returns nothing into filled ones here.
    std::vector<std::size_t> line_elements, nodes;
    gmsh::model::mesh::getElementsByType(1, line_elements, nodes, l);
    auto& segments = out.segments[g];
    segments.insert(segments.end(), nodes.begin(), nodes.end());
  }
  return out;
}

/// The element size of the air (build()): size_nozzle in the bore and a
/// bore radius beyond its exit; size_jet in a cylinder of jet_radius about
/// the axis, from the inlet down to below the apex. Each grows by
/// size_gradation per mm of distance from its region, up to size_far.
std::function<double(double, double, double)> size_field(const Domain& d, double apex_y)
{
  const double y_exit = apex_y + d.nozzle_distance, y_top = y_exit + d.nozzle_length,
               y_low = apex_y - d.jet_radius, bore = d.nozzle_diameter / 2;
  // Distance from (r, y) to the cylinder r <= radius, lo <= y <= hi.
  const auto away = [](double r, double y, double radius, double lo, double hi) {
    return std::hypot(std::max(0.0, r - radius), std::max({0.0, y - hi, lo - y}));
  };
  return [=](double x, double y, double z) {
    const double r = std::hypot(x, z);
    const double h = std::min(
        d.size_nozzle + d.size_gradation * away(r, y, bore, y_exit - bore, y_top),
        d.size_jet + d.size_gradation * away(r, y, d.jet_radius, y_low, y_top));
    return std::min(d.size_far, h);
  };
}

/// The air's nodes meshed in a temporary model, in the current one: the
/// eye's node where it is one (`eye`), else a tag after the current
/// model's largest.
class NodeTags
{
public:
  explicit NodeTags(const std::map<std::size_t, std::size_t>& eye) : _eye(eye)
  {
    std::vector<std::size_t> tags;
    std::vector<double> xyz, uvw;
    gmsh::model::mesh::getNodes(tags, xyz, uvw, -1, -1, false, false);
    for (std::size_t t : tags)
      _offset = std::max(_offset, t);
  }
  std::size_t operator()(std::size_t n) const
  {
    auto it = _eye.find(n);
    return it != _eye.end() ? it->second : _offset + n;
  }
  /// The nodes of `x` that are not the eye's, into the entity (dim, tag).
  void add_nodes(int dim, int tag, const std::map<std::size_t, Vec3>& x) const
  {
    std::vector<std::size_t> tags;
    std::vector<double> coords;
    for (auto& [n, p] : x)
      if (!_eye.count(n))
      {
        tags.push_back(_offset + n);
        coords.insert(coords.end(), p.begin(), p.end());
      }
    gmsh::model::mesh::addNodes(dim, tag, tags, coords);
  }

private:
  const std::map<std::size_t, std::size_t>& _eye;
  std::size_t _offset = 0;
};

} // namespace

void validate(const Domain& d, double apex_y, double bottom_y, double eye_radius)
{
  if (!(d.nozzle_diameter > 0))
    reject("air.nozzle_diameter", d.nozzle_diameter, "must be > 0");
  if (!(d.nozzle_outer_diameter > d.nozzle_diameter))
    reject("air.nozzle_outer_diameter", d.nozzle_outer_diameter,
           "must exceed air.nozzle_diameter");
  if (!(d.radius > d.nozzle_outer_diameter / 2 + d.size_jet))
    reject("air.radius", d.radius, "must exceed the nozzle's outer radius by an element");
  if (!(d.nozzle_distance > 0))
    reject("air.nozzle_distance", d.nozzle_distance, "must be > 0");
  if (!(d.nozzle_length > 0))
    reject("air.nozzle_length", d.nozzle_length, "must be > 0");
  if (!(d.size_jet > 0 && d.size_jet <= d.size_far))
    reject("air.size_jet", d.size_jet, "must be > 0 and <= air.size_far");
  if (!(d.size_nozzle > 0 && d.size_nozzle <= d.size_far))
    reject("air.size_nozzle", d.size_nozzle, "must be > 0 and <= air.size_far");
  if (!(apex_y > bottom_y))
    reject("geometry.cut_y", bottom_y, "must lie below the corneal apex");
  if (eye_radius > 0 && !(d.nozzle_distance >= 10))
    reject("air.nozzle_distance", d.nozzle_distance,
           "must be >= 10 mm with the eye (the centreline is sampled 2 to 10 mm from the exit)");
  if (!(d.radius > eye_radius + d.size_jet))
    reject("air.radius", d.radius, "must exceed the eye's radius (geometry.sclera_outer_radius)");
}

void build(const Domain& d, double apex_y, double bottom_y, double eye_radius, bool around_eye)
{
  validate(d, apex_y, bottom_y, eye_radius);
  const auto size = size_field(d, apex_y);

  try
  {
    meshio::OptionGuard quiet;
    quiet.set("General.Terminal", 0);
    std::string model = "air";
    Rim rim;
    if (around_eye)
    {
      gmsh::model::getCurrent(model);
      rim = eye_rim(bottom_y);
    }
    else
      gmsh::model::add(model);
    const Surfaces s = mesh_boundary(d, apex_y, bottom_y, around_eye ? &rim : nullptr, size);
    gmsh::model::setCurrent(model);

    // The air's boundary as discrete surfaces.
    const NodeTags tag_of(s.eye);
    const int first = 101;
    std::vector<int> loop;
    std::map<int, std::vector<int>> groups;
    for (std::size_t i = 0; i < s.triangles.size(); ++i)
    {
      const int entity = first + static_cast<int>(i);
      gmsh::model::addDiscreteEntity(2, entity);
      loop.push_back(entity);
      groups[s.triangles[i].first].push_back(entity);
    }
    tag_of.add_nodes(2, first, s.x);
    for (std::size_t i = 0; i < s.triangles.size(); ++i)
    {
      std::vector<std::size_t> nodes;
      for (std::size_t n : s.triangles[i].second)
        nodes.push_back(tag_of(n));
      gmsh::model::mesh::addElementsByType(first + static_cast<int>(i), 2, {}, nodes);
    }
    if (around_eye)
      loop.insert(loop.end(), {1, 2}); // the eye's anterior surfaces
    // Nodes to the lowest-dimensional entity whose elements use them (the
    // eye's were put in bulk on its volumes): the volume mesher must see
    // the boundary's nodes on the boundary.
    gmsh::model::mesh::reclassifyNodes();

    // The air volume, meshed from its closed boundary.
    const int volume = static_cast<int>(Group::volume);
    gmsh::model::geo::addVolume({gmsh::model::geo::addSurfaceLoop(loop)}, volume);
    gmsh::model::geo::synchronize();
    generate(3, size, true);

    gmsh::model::addPhysicalGroup(3, {volume}, volume);
    gmsh::model::setPhysicalName(3, volume, "air");
    const std::map<int, std::string> names{
        {static_cast<int>(Group::inlet), "inlet"},
        {static_cast<int>(Group::outlet), "outlet"},
        {static_cast<int>(Group::nozzle), "nozzle"},
        {static_cast<int>(Group::symmetry_x), "air_symmetry_x"},
        {static_cast<int>(Group::symmetry_z), "air_symmetry_z"}};
    for (auto& [group, entities] : groups)
    {
      gmsh::model::addPhysicalGroup(2, entities, group);
      gmsh::model::setPhysicalName(2, group, names.at(group));
    }
  }
  catch (const std::string& message) // gmsh 4.8 throws its last error as a string
  {
    throw std::runtime_error("nct::air::build: gmsh failed: " + message);
  }
}

void build_section(const Domain& d, double apex_y, double bottom_y, double eye_radius,
                   bool around_eye)
{
  validate(d, apex_y, bottom_y, eye_radius);
  try
  {
    meshio::OptionGuard quiet;
    quiet.set("General.Terminal", 0);
    std::string model = "air";
    std::vector<std::size_t> profile;
    std::map<std::size_t, Vec3> profile_x;
    if (around_eye)
    {
      gmsh::model::getCurrent(model);
      std::tie(profile, profile_x) = eye_profile();
    }
    else
      gmsh::model::add(model);
    const Section s = mesh_section(d, apex_y, bottom_y, around_eye ? &profile : nullptr,
                                   around_eye ? &profile_x : nullptr, size_field(d, apex_y));
    gmsh::model::setCurrent(model);

    // The air as a discrete surface and curves.
    const NodeTags tag_of(s.eye);
    const int surface = static_cast<int>(Group::volume);
    gmsh::model::addDiscreteEntity(2, surface);
    tag_of.add_nodes(2, surface, s.x);
    std::vector<std::size_t> nodes;
    for (std::size_t n : s.triangles)
      nodes.push_back(tag_of(n));
    gmsh::model::mesh::addElementsByType(surface, 2, {}, nodes);
    gmsh::model::addPhysicalGroup(2, {surface}, surface);
    gmsh::model::setPhysicalName(2, surface, "air");
    const std::map<int, std::string> names{{static_cast<int>(Group::inlet), "inlet"},
                                           {static_cast<int>(Group::outlet), "outlet"},
                                           {static_cast<int>(Group::nozzle), "nozzle"},
                                           {static_cast<int>(Group::axis), "air_axis"}};
    for (auto& [group, segments] : s.segments)
    {
      const int curve = 100 + group;
      gmsh::model::addDiscreteEntity(1, curve);
      nodes.clear();
      for (std::size_t n : segments)
        nodes.push_back(tag_of(n));
      gmsh::model::mesh::addElementsByType(curve, 1, {}, nodes);
      gmsh::model::addPhysicalGroup(1, {curve}, group);
      gmsh::model::setPhysicalName(1, group, names.at(group));
    }
  }
  catch (const std::string& message) // gmsh 4.8 throws its last error as a string
  {
    throw std::runtime_error("nct::air::build_section: gmsh failed: " + message);
  }
}

} // namespace nct::air
