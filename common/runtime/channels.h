#pragma once
// LCM channel names of the task runtime and the scheduler.

namespace ephor::channels {

inline constexpr const char* kTaskRegister = "EPHOR_TASK_REGISTER";  // task_register_t
inline constexpr const char* kTaskJobs = "EPHOR_TASK_JOBS";          // task_jobs_t
inline constexpr const char* kTaskTrigger = "EPHOR_TASK_TRIGGER";    // task_trigger_t
inline constexpr const char* kSchedAssign = "EPHOR_SCHED_ASSIGN";    // sched_assignments_t
inline constexpr const char* kSchedStatus = "EPHOR_SCHED_STATUS";    // sched_status_t
// Deputy/sheriff (procs/shared/deputy, procs/shared/sheriff).
inline constexpr const char* kDeputyOrders =
    "EPHOR_DEPUTY_ORDERS";  // deputy_orders_t, sheriff -> deputies
inline constexpr const char* kDeputyStatus = "EPHOR_DEPUTY_STATUS";  // deputy_status_t, 1 Hz
inline constexpr const char* kDeputyOutput = "EPHOR_DEPUTY_OUTPUT";  // deputy_output_t

}  // namespace ephor::channels
