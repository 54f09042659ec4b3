#pragma once
// The task messages ephor-scheduler takes (task_register_t, task_jobs_t) as
// the Scheduler's Registration and JobsReport (moved out of main.cc so the
// fuzz target task_messages_fuzz.cc runs what the process runs). Messages
// of other hosts are for other schedulers: nullopt.

#include <optional>
#include <string>

#include "ephor/task_jobs_t.hpp"
#include "ephor/task_register_t.hpp"
#include "procs/shared/scheduler/scheduler.h"

namespace ephor::scheduler {

std::optional<Registration> registration_of(const task_register_t& m, const std::string& host);
std::optional<JobsReport> jobs_report_of(const task_jobs_t& m, const std::string& host);

}  // namespace ephor::scheduler
