// The resumable run cache of studies, fits and cohorts (jobs::RunCache):
// what a run folder records, when it counts as finished and agrees, how a
// run is made ready to start again, and which runs a resumed fit removes.
// (tests/study_resume.py, fit_check.py's resume and cohort_check.py resume
// whole drivers.)
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

#include "jobs/jobs.h"
#include "io/text.h"
#include "jobs/run_cache.h"

namespace fs = std::filesystem;
using nct::jobs::RunCache;

namespace
{

/// An empty folder of its own under the temporary folder.
fs::path fresh(const std::string& name)
{
  const fs::path dir = fs::temp_directory_path() / ("nct_run_cache_" + name);
  fs::remove_all(dir);
  return dir;
}

void write(const fs::path& file, const std::string& text)
{
  fs::create_directories(file.parent_path());
  std::ofstream(file) << text;
}

} // namespace

// A study's case.json as an nct without the scene's record wrote it: the
// case still agrees with the same overrides, and is finished once it has
// its summary; other overrides mean another study.
TEST(RunCache, OlderCaseRecordWithoutItsSceneAgrees)
{
  const fs::path dir = fresh("older");
  RunCache cases(dir, "case.json", "summary.json");
  write(dir / "case-001" / "case.json",
        R"({"case": "case-001", "sets": ["inflate.iop=8"]})");
  nlohmann::json wanted = nct::jobs::run_record("scenes/default.toml", {"inflate.iop=8"});
  wanted["case"] = "case-001";
  EXPECT_TRUE(cases.agrees("case-001", wanted));
  EXPECT_FALSE(cases.finished("case-001"));
  write(dir / "case-001" / "summary.json", "{}");
  EXPECT_TRUE(cases.reusable("case-001", wanted));
  wanted["sets"] = {"inflate.iop=9"};
  EXPECT_FALSE(cases.agrees("case-001", wanted));
  EXPECT_FALSE(cases.reusable("case-001", wanted));
  // A run without a record agrees with anything, and is not finished.
  write(dir / "case-002" / "summary.json", "{}");
  EXPECT_TRUE(cases.agrees("case-002", wanted));
  EXPECT_FALSE(cases.finished("case-002"));
}

// nct run's job: its command line, its console, and its record written
// (as the study's case.json was) only when it starts, into a cleared folder.
TEST(RunCache, NctRunStartsAfreshWithItsRecord)
{
  const fs::path dir = fresh("afresh");
  RunCache runs(dir, "case.json", "summary.json");
  write(dir / "case-001" / "half-written.csv", "t_ms\n");
  nct::jobs::Job job = runs.nct_run("case-001", "/bin/nct", "/scenes/a.toml", {"x.y=1"}, 2,
                                    "mpiexec", {{"case", "case-001"}});
  // A case's run writes no page: its study's covers it.
  EXPECT_EQ(job.argv, (std::vector<std::string>{"/bin/nct", "run", "/scenes/a.toml", "--set",
                                                "x.y=1", "--out", (dir / "case-001").string(),
                                                "--no-report"}));
  EXPECT_EQ(job.log, fs::absolute(dir / "case-001" / "console.log"));
  EXPECT_EQ(job.ranks, 2);
  EXPECT_FALSE(fs::exists(dir / "case-001" / "case.json"));
  ASSERT_TRUE(job.prepare);
  job.prepare();
  EXPECT_FALSE(fs::exists(dir / "case-001" / "half-written.csv"));
  EXPECT_EQ(nct::io::read_text(dir / "case-001" / "case.json"),
            "{\n  \"case\": \"case-001\",\n  \"scene\": \"/scenes/a.toml\",\n  \"sets\": [\n"
            "    \"x.y=1\"\n  ]\n}\n");
}

// A cohort's patient starts again in its folder: its fit resumes from
// what it holds; only its old answer goes, and its new row is recorded.
TEST(RunCache, ResumingRunKeepsItsFolderButItsResult)
{
  const fs::path dir = fresh("resume");
  RunCache patients(dir, "patient.json", "fit.json");
  write(dir / "A" / "patient.json", R"({"patient": "A", "sets": ["inflate.iop=15"]})");
  write(dir / "A" / "fit.json", "{}");
  write(dir / "A" / "runs" / "run-0001" / "summary.json", "{}");
  const nlohmann::json row = {{"patient", "A"}, {"sets", {"inflate.iop=16"}}};
  EXPECT_TRUE(patients.finished("A"));
  EXPECT_FALSE(patients.reusable("A", row));
  nct::jobs::Job job{{"nct", "fit"}, dir / "A" / "fit.log", 1, "", nullptr};
  patients.prepare(job, "A", row, RunCache::Restart::resume);
  job.prepare();
  EXPECT_FALSE(fs::exists(dir / "A" / "fit.json"));
  EXPECT_TRUE(fs::exists(dir / "A" / "runs" / "run-0001" / "summary.json"));
  EXPECT_EQ(patients.recorded("A"), row);
}

// A fit started again keeps its finished forward runs and removes the
// interrupted ones and those without a record (none is in flight on this
// machine).
TEST(RunCache, CleanRemovesWhatCannotBeReused)
{
  const fs::path dir = fresh("clean");
  RunCache runs(dir, "run.json", "summary.json");
  write(dir / "run-0001" / "run.json", R"({"sets": ["a=1"]})");
  write(dir / "run-0001" / "summary.json", "{}");
  write(dir / "run-0002" / "run.json", R"({"sets": ["a=2"]})");
  write(dir / "run-0003" / "console.log", "");
  EXPECT_EQ(runs.names(), (std::vector<std::string>{"run-0001", "run-0002", "run-0003"}));
  EXPECT_TRUE(runs.clean(nct::jobs::Launcher{}).empty());
  EXPECT_EQ(runs.names(), (std::vector<std::string>{"run-0001"}));
  EXPECT_EQ(runs.recorded("run-0001")["sets"], (std::vector<std::string>{"a=1"}));
  EXPECT_TRUE(runs.recorded("run-0002").is_null());
}
