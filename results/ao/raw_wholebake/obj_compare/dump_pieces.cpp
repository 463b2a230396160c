// dump.cpp reading through detail::read_obj with pieces of $PIECE bytes, at most $MAXP (the
// branch's reader only): its output against dump.cpp's checks that pieces read like one pass.
#include <cstdio>
#include <cstdlib>
#include "rtmini/io/obj_reader.hpp"
#include "rtmini/io/error.hpp"
using namespace rtmini;
int main(int argc, char** argv) {
  for (int a = 1; a < argc; ++a) {
    std::printf("== %s\n", argv[a]);
    try {
      const Mesh m = getenv("PIECE") ? detail::read_obj(argv[a], atoi(getenv("PIECE")), atoi(getenv("MAXP"))) : read_obj(argv[a]);
      std::printf("pos %zu faces %zu tc %zu mat %zu obj %zu\n", m.positions.size(), m.faces.size(), m.texcoords.size(), m.materials.size(), m.objects.size());
      for (auto& p : m.positions) std::printf("v %a %a %a\n", (float)p.x, (float)p.y, (float)p.z);
      for (auto& t : m.texcoords) std::printf("vt %a %a\n", t.u, t.v);
      for (auto& f : m.faces) std::printf("f %d %d %d %d %d | %d %d %d %d | m%d o%d\n", f.count, f.v[0], f.v[1], f.v[2], f.v[3], f.uv[0], f.uv[1], f.uv[2], f.uv[3], f.material, f.object);
      for (auto& o : m.objects) std::printf("o [%s]\n", o.c_str());
      for (auto& mt : m.materials) std::printf("mat [%s] %a %a %a %s\n", mt.name.c_str(), mt.diffuse.x, mt.emissive.x, mt.opacity, mt.maps.diffuse.c_str());
    } catch (const std::exception& e) { std::printf("ERR %s\n", e.what()); }
  }
}
