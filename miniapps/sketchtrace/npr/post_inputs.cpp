#include "post_inputs.hpp"

#include "rtmini/io/error.hpp"
#include "rtmini/io/path.hpp"

namespace rtmini::npr {

NprInputs PostImages::inputs() const {
  NprInputs in;
  in.color = &color;
  in.edge = has_edge ? &edge : nullptr;
  in.depth = has_depth ? &depth : nullptr;
  in.object = has_object ? &object : nullptr;
  in.normal = has_normal ? &normal : nullptr;
  return in;
}

namespace {
bool is_exr(const std::string& path) { return lower_extension(path) == ".exr"; }
}  // namespace

PostImages read_post_images(const std::string& path) {
  PostImages li;
  if (!is_exr(path)) {
    li.color = read_image(path);
    return li;
  }
  const auto layers = read_exr_layers(path);
  const Image* nx = nullptr;
  const Image* ny = nullptr;
  const Image* nz = nullptr;
  const Image* grey = nullptr;
  bool has_color = false;
  for (const auto& [name, image] : layers) {
    if (name.empty() && image.channels >= 3) {
      li.color = image;
      has_color = true;
    } else if (name == "edge.Y" || name == "edge") {
      li.edge = image;
      li.has_edge = true;
    } else if (name == "depth.Z" || name == "depth") {
      li.depth = image;
      li.has_depth = true;
    } else if (name == "object.Y" || name == "object") {
      li.object = image;
      li.has_object = true;
    } else if (name == "normal" && image.channels >= 3) {
      li.normal = image;
      li.has_normal = true;
    } else if (name == "normal.X") {
      nx = &image;
    } else if (name == "normal.Y") {
      ny = &image;
    } else if (name == "normal.Z") {
      nz = &image;
    } else if (name == "Y") {
      grey = &image;
    }
  }
  if (!has_color && grey != nullptr) {
    li.color = *grey;
    has_color = true;
  }
  if (!has_color) throw InputError(path, 0, "no colour layer (R, G, B or Y channels)");
  if (!li.has_normal && nx && ny && nz) {
    li.normal = Image(nx->width, nx->height, 3);
    for (std::size_t i = 0; i < nx->data.size(); ++i) {
      li.normal.data[3 * i] = nx->data[i];
      li.normal.data[3 * i + 1] = ny->data[i];
      li.normal.data[3 * i + 2] = nz->data[i];
    }
    li.has_normal = true;
  }
  return li;
}

}  // namespace rtmini::npr
