// BVH (Biovision hierarchy) motion files: a joint hierarchy with offsets and
// channel layouts, then one line of channel values per frame.
//
// Every joint (and End Site, named "<parent>_end") becomes a body of the
// MarkerData whose pose per frame comes from forward kinematics: a joint's
// local transform is a translation (OFFSET plus any position channels)
// followed by the rotation channels composed in the order listed
// ("Zrotation Xrotation Yrotation" → R = Rz·Rx·Ry), in degrees. Lengths stay
// in the file's unit (BVH has none; see GuessBvhScaleToMetres), Y is up.
#pragma once

#include <string>
#include <string_view>

#include "common/marker_data.h"

namespace syn {

struct BvhOptions {
  // Drop frame 0: cgspeed's MotionBuilder- and Daz-friendly CMU conversions
  // put a T-pose / reference frame there that is not part of the take. Frames
  // right after it with every channel exactly zero (a second reference frame,
  // as in 07_12) are dropped too, and so are the frames that ease in from it
  // (bvh_reader.cpp, EaseInEnd: some copies of CMU blend from the rest pose into
  // the take over 4-5 frames), and a lead-in of up to 0.5 s that ends where a
  // joint jumps faster than any body moves (kTeleportSpeed: CMU 03_02 holds its
  // T-pose arms for 50 frames of its walk, then its hands jump 69 cm in a frame),
  // and a run of frames repeating one pose exactly before the take moves (08_07).
  bool drop_first_frame = false;
};

// Throws DataError at file:line for malformed input (braces, unknown
// channels, wrong value counts, non-numeric values, missing frames).
[[nodiscard]] MarkerData ParseBvh(std::string_view text, const std::string& source_name, const BvhOptions& options);
[[nodiscard]] MarkerData ReadBvh(const std::string& path, const BvhOptions& options);

// Metres per BVH unit, from the skeleton's standing height in its rest pose
// (all channels zero; stored in metadata "rest_height_units" by ParseBvh):
//   10–50 units   → 0.056444: CMU's ASF length unit (1/0.45 inch), used by
//                   cgspeed's MotionBuilder- and 3dsMax-friendly conversions
//                   (CMU skeletons measure 25–26 units, i.e. 1.42–1.46 m);
//   50–100 units  → 0.0254 (inches);
//   100–250 units → 0.01 (centimetres: cgspeed's Daz-friendly files, 152.7 units);
//   1–2.5 units   → 1 (metres);
//   anything else → 1, and a warning.
[[nodiscard]] double GuessBvhScaleToMetres(MarkerData& data);

}  // namespace syn
