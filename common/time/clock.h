#pragma once
// Clocks used across ephor. Monotonic time (CLOCK_MONOTONIC) is for
// periods, latencies and deadlines on one host; wall time (CLOCK_REALTIME) is
// what messages carry in `utime`, comparable across hosts only as far as their
// clocks are synchronised (e.g. by NTP/PTP).

#include <cstdint>
#include <ctime>

namespace ephor {

// CLOCK_MONOTONIC in nanoseconds.
int64_t mono_ns();
// CLOCK_MONOTONIC in microseconds.
inline int64_t mono_us() { return mono_ns() / 1000; }
// CPU time used by the calling thread (CLOCK_THREAD_CPUTIME_ID), ns.
int64_t thread_cpu_ns();
// CLOCK_REALTIME in microseconds since the Unix epoch (the `utime` of messages).
int64_t wall_us();

timespec ns_to_timespec(int64_t ns);
int64_t timespec_to_ns(const timespec& ts);

// Sleeps until an absolute CLOCK_MONOTONIC time (ns), restarting on EINTR.
void sleep_until_mono_ns(int64_t deadline_ns);

}  // namespace ephor
