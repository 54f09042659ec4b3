#pragma once
// The peer (issue 15): PCL's sphere RANSAC on the same foreground points.
// Built only when PCL is found; otherwise pcl_peer_available() is false.

#include "common/sphere/scan_types.h"

namespace ephor::sphere {

bool pcl_peer_available();
Estimate pcl_sphere_locate(const Window& window);

}  // namespace ephor::sphere
