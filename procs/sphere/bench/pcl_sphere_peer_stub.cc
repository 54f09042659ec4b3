// Without PCL: the peer is absent, and the benchmark says so.
#include "procs/sphere/bench/pcl_sphere_peer.h"

namespace ephor::sphere {

bool pcl_peer_available() { return false; }
Estimate pcl_sphere_locate(const Window&) { return Estimate::none("PCL not built"); }

}  // namespace ephor::sphere
