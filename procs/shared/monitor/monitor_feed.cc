#include "procs/shared/monitor/monitor_feed.h"

#include <vector>

#include "common/runtime/counts.h"

namespace ephor::monitor {

void MonitorFeed::on_truth(const shepherd_ground_truth_t& m) {
  Truth t;
  t.utime = m.utime;
  t.escapes = m.escapes;
  t.saves = m.saves;
  t.sim_time_s = m.sim_time_s;
  for (const auto& s : m.sheep)
    t.sheep.push_back({s.id, s.x_mm, s.y_mm, s.u, s.v, s.visible != 0, s.on_field != 0});
  monitor_.on_truth(t);
}

void MonitorFeed::on_blobs(const shepherd_blobs_t& m, int64_t now_us) {
  monitor_.on_blobs(m.utime, m.header.utime, now_us);
}

void MonitorFeed::on_objects(const shepherd_objects_t& m, int64_t now_us) {
  std::vector<TrackedObject> objects;
  for (const auto& o : m.objects)
    objects.push_back({o.id, o.state == shepherd_object_t::STATE_VISIBLE,
                       o.state == shepherd_object_t::STATE_DEAD, o.x_mm, o.y_mm, o.u, o.v});
  monitor_.on_objects(m.utime, m.header.utime, objects, now_us);
}

void MonitorFeed::on_arm_goal(const arm_goal_t& m) {
  monitor_.on_arm_goal(m.source_frame_utime, m.header.utime);
}

void MonitorFeed::on_arm_cmd(const arm_cmd_t& m) {
  if (!seen_cmds_.insert({m.header.sender, m.seq}).second) return;
  monitor_.on_arm_command(m.source_frame_utime, m.header.utime);
}

void MonitorFeed::on_sched_status(const sched_status_t& m) {
  int64_t misses = 0;
  for (const auto& t : m.tasks) misses = add_count(misses, t.deadline_misses);
  hosts_[m.host] = {m.rt != 0, misses};
  bool rt = true;
  int64_t total = 0;
  for (const auto& [host, h] : hosts_) {
    rt = rt && h.first;
    total = add_count(total, h.second);
  }
  monitor_.on_sched_status(rt, total);
}

}  // namespace ephor::monitor
