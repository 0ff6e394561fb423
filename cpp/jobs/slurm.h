// Jobs on a Slurm cluster: one job array per batch of jobs (a task per
// job, at most `at_once` running), followed with Slurm's own squeue; the
// submissions recorded in the launcher's folder, so that a driver started
// again finds its jobs still queued or running instead of submitting them
// twice.
#pragma once

#include <functional>
#include <set>
#include <string>
#include <vector>

#include "jobs/jobs.h"

namespace nct::jobs::slurm
{

/// Check that Slurm takes the launcher's options, before anything is
/// submitted: sbatch on the PATH, the partition known, and
/// `sbatch --test-only` accepting the partition, account, time limit, cores
/// and options for a job of `ranks` ranks. Throws std::runtime_error
/// naming the key under `prefix` ("study.slurm.") that Slurm refused.
void check(const Launcher& launcher, int ranks, const std::string& prefix);

/// The logs (absolute paths) of the jobs the launcher's folder records as
/// submitted whose tasks are still queued or running; none for a local
/// launcher.
std::set<std::string> in_flight(const Launcher& launcher);

/// Run `jobs` as Slurm job arrays (see jobs::run): each task runs its job
/// (`srun --mpi=pmix -n ranks` for ranks > 1) with its output in its log and
/// its exit code in "<log>.exit". Jobs the folder's record shows queued or
/// running are followed, not submitted again. A task that ends without an
/// exit code (cancelled, out of time, its node lost) counts as failed, with
/// Slurm's state appended to its log. On SIGINT or SIGTERM every submitted
/// task not yet ended is cancelled (scancel), and this says so.
bool run(const Launcher& launcher, const std::vector<Job>& jobs, int at_once,
         const std::function<void(std::size_t, int)>& done);

} // namespace nct::jobs::slurm
