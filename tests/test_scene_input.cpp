// Scene files: defaults, overrides, and the errors bad input gets.
#include <fstream>
#include <gtest/gtest.h>

#include "scene/scene.h"

using nct::scene::Error;
using nct::scene::Scene;

namespace
{
std::filesystem::path source(const std::string& p)
{
  return std::filesystem::path(NCT_SOURCE_DIR) / p;
}

/// The message of the Error that loading `text` (with overrides) throws.
std::string error_of(const std::string& text, const std::vector<std::string>& sets = {})
{
  auto file = std::filesystem::temp_directory_path() / "nct_test_scene.toml";
  std::ofstream(file) << text;
  try
  {
    Scene::load(file, sets);
  }
  catch (const Error& e)
  {
    return e.what();
  }
  return "";
}
} // namespace

TEST(Scene, DefaultsFillWhatTheFileOmits)
{
  Scene s = Scene::load(source("scenes/inflate.toml"));
  EXPECT_EQ(s.integer("mesh.layers"), 5);
  EXPECT_DOUBLE_EQ(s.real("material.cornea.c10"), 0.05);
  EXPECT_DOUBLE_EQ(s.real("material.sclera.c10"), 0.8);
  EXPECT_EQ(s.string("material.sclera.model"), "neo_hookean");
  EXPECT_FALSE(s.has("mesh.file")); // applies to file meshes only
  // The resolved scene reloads to the same values.
  auto file = std::filesystem::temp_directory_path() / "nct_resolved.toml";
  std::ofstream(file) << s.to_toml();
  Scene r = Scene::load(file);
  EXPECT_DOUBLE_EQ(r.real("geometry.cut_y"), s.real("geometry.cut_y"));
  EXPECT_EQ(r.tables("material"), s.tables("material"));
}

TEST(Scene, OverridesWinAndAreChecked)
{
  Scene s = Scene::load(source("scenes/inflate.toml"),
                        {"mesh.layers=3", "material.cornea.k2=150", "solver.petsc.ksp_type=cg"});
  EXPECT_EQ(s.integer("mesh.layers"), 3);
  EXPECT_DOUBLE_EQ(s.real("material.cornea.k2"), 150);
  EXPECT_EQ(s.options("solver.petsc").at(0), std::make_pair(std::string("ksp_type"),
                                                             std::string("cg")));
  EXPECT_THROW(Scene::load(source("scenes/inflate.toml"), {"mesh.layers"}), Error);
}

TEST(Scene, WildcardMaterialsGetDefaults)
{
  Scene s = Scene::load(source("tests/scenes/sphere_inflation.toml"));
  EXPECT_EQ(s.tables("material"), std::vector<std::string>{"shell"});
  EXPECT_DOUBLE_EQ(s.real("material.shell.poisson_ratio"), 0.3);
  EXPECT_TRUE(s.points("material.shell.fibre_directions").empty());
}

TEST(Scene, ErrorsNameTheKeyAndWhatIsAccepted)
{
  EXPECT_NE(error_of("[fem]\ndegree = 2.5\n").find("key 'fem.degree'"), std::string::npos);
  EXPECT_NE(error_of("[inflate]\nsteps = 0\n").find("[1, 10000]"), std::string::npos);
  EXPECT_NE(error_of("[material.cornea]\nk1 = -1.0\n").find("material.cornea.k1"),
            std::string::npos);
  EXPECT_NE(error_of("[output]\nprobes = [[1.0, 2.0]]\n").find("[x, y, z]"),
            std::string::npos);
  EXPECT_NE(error_of("[mesh]\nlayers = 5\n[mesh.extra]\nx = 1\n").find("mesh.extra.x"),
            std::string::npos);
  EXPECT_NE(error_of("[material.lens]\nc10 = 1.0\n").find("mesh.source=file"),
            std::string::npos);
  EXPECT_NE(error_of("", {"inflate.iop=abc"}).find("--set inflate.iop=abc"),
            std::string::npos);
  EXPECT_NE(error_of("[solver.petsc]\nksp_type = [1]\n").find("ksp_type"), std::string::npos);
}

// An override that switches an effect off leaves the file's keys for it
// unused: they are ignored with a note naming them and the option. A key
// the file itself switched off, or one set on the command line against
// the file's switch, stays an error.
TEST(Scene, KeysAnOverrideTurnedOffAreIgnoredWithANote)
{
  auto file = std::filesystem::temp_directory_path() / "nct_test_switched.toml";
  std::ofstream(file) << "[support]\nmodel = \"springs\"\nstiffness = 0.5\n";
  Scene s = Scene::load(file, {"support.model=clamped"});
  EXPECT_FALSE(s.has("support.stiffness"));
  ASSERT_EQ(s.notes().size(), 1u);
  EXPECT_NE(s.notes()[0].find("nct_test_switched.toml:3: key 'support.stiffness'"),
            std::string::npos)
      << s.notes()[0];
  EXPECT_NE(s.notes()[0].find("--set support.model=clamped"), std::string::npos);
  EXPECT_TRUE(Scene::load(file).notes().empty());
  EXPECT_NE(error_of("[support]\nmodel = \"clamped\"\nstiffness = 0.5\n")
                .find("applies only when support.model=springs"),
            std::string::npos);
  EXPECT_NE(error_of("[support]\nmodel = \"clamped\"\n", {"support.stiffness=0.5"})
                .find("applies only when support.model=springs"),
            std::string::npos);
}

TEST(Scene, DescribeDocumentsEveryKey)
{
  const std::string text = nct::scene::describe(true);
  for (const auto& key : nct::scene::keys())
  {
    EXPECT_NE(text.find("`" + key.name + "`"), std::string::npos) << key.name;
    EXPECT_FALSE(key.description.empty()) << key.name;
  }
}
