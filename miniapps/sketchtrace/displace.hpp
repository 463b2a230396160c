#pragma once
// True displacement, the reference that measures parallax occlusion mapping's error
// (issue 24): every face of a material with a height field (MTL disp) and texture
// coordinates is replaced on load by a grid of 2^level x 2^level cells whose vertices move
// along the face normal by (h - 1) x scale, the same surface parallax.hpp marches (h = 1
// on the polygon, h = 0 at depth `scale`). The face's border stays on the polygon so the
// grid meets its undisplaced neighbours without cracks. The displaced faces lose their
// height map (their geometry now has the detail).
#include <vector>

#include "surface_maps.hpp"

namespace rtmini::sketch {

// How height fields are rendered: marched in the kernel, tessellated and displaced on load, or
// ignored (the flat polygon).
enum class DisplacementMode { kParallax, kTessellate, kOff };

DisplacementMode parse_displacement_mode(const std::string& name);

// h at (u, v) of a height image, bilinear with wrapping, as the device's level 0 (textures.hpp).
float height_at(const Image& image, double u, double v);

// Tessellates and displaces (kTessellate) or drops (kOff) the height fields of `mesh`;
// kParallax leaves it as it is. Returns the number of faces replaced.
std::size_t apply_displacement_mode(Mesh& mesh, const std::vector<MapImage>& images,
                                    DisplacementMode mode, int level);

}  // namespace rtmini::sketch
