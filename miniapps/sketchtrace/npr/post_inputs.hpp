#pragma once
// A saved render as NPR inputs: an EXR with the renderer's AOV layers
// ("R","G","B", "edge.Y", "depth.Z", "object.Y", "normal.X/Y/Z" or a normal
// R/G/B group), or a PNG/PPM that carries colour only.
#include <string>

#include "npr.hpp"
#include "rtmini/io/image.hpp"

namespace rtmini::npr {

struct PostImages {
  Image color, edge, depth, object, normal;
  bool has_edge = false, has_depth = false, has_object = false, has_normal = false;

  // Pointers into this object: it must outlive the returned inputs.
  NprInputs inputs() const;
};

// InputError "file: reason" when an EXR has no colour layer.
PostImages read_post_images(const std::string& path);

}  // namespace rtmini::npr
