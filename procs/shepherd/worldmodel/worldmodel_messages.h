#pragma once
// ephor-worldmodel's messages in and out, as its associate task converts
// them (out of main.cc, so that the fuzz target worldmodel_messages_fuzz.cc
// runs what the process runs): a BLOBS message checked and taken as the
// WorldModel's frame, the model's objects as the OBJECTS message it
// publishes.

#include <cstdint>

#include "common/shepherd/worldmodel/world_model.h"
#include "ephor/shepherd_blobs_t.hpp"
#include "ephor/shepherd_objects_t.hpp"

namespace ephor::worldmodel {

// False when num_blobs is not the number of blobs: a broken sender (lcm-gen
// sizes the array from num_blobs); the task ignores such a frame.
bool blobs_consistent(const shepherd_blobs_t& msg);

// The frame as WorldModel::process() takes it: capture utime (us), frame
// index and every blob's centroid (image px) and area (px), unchecked (the
// model counts and ignores non-finite centres and areas <= 0).
BlobFrame frame_of(const shepherd_blobs_t& msg);

// Every object of the model as of its last frame (live and recently dead,
// by id) as published: the frame's capture utime, `frame_index` of the BLOBS
// it came from, positions in px and F (mm, at the mark height), velocities
// in px/s and mm/s. The header is the bus's to set.
shepherd_objects_t objects_message_of(const WorldModel& wm, int64_t frame_index);

}  // namespace ephor::worldmodel
