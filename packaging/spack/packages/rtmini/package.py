# Spack recipe for rtmini, kept with the sources so it changes with the CMake options it maps.
# Use it as a local repository:
#   spack repo add packaging/spack
#   spack install rtmini@main +cuda cuda_arch=90 ^kokkos@4.6 +cuda_lambda
# tests/repo/test_spack_package.py checks that every variant below maps to an RTMINI_* option
# that CMakeLists.txt declares (or to the Kokkos backend), so a renamed option fails ctest.
from spack.package import *


class Rtmini(CMakePackage, CudaPackage):
    """Kokkos + MPI ray-tracing mini-apps (bake, sketchtrace) and their shared library."""

    homepage = "https://example.invalid/rtmini"
    git = "https://example.invalid/rtmini.git"

    license("UNKNOWN")

    version("main", branch="main")

    # Variants that switch one rtmini CMake option (cmake_args below uses this table).
    variant_options = {
        "mpi": "RTMINI_ENABLE_MPI",
        "hdf5": "RTMINI_ENABLE_HDF5",
        "png": "RTMINI_ENABLE_PNG",
        "exr": "RTMINI_ENABLE_EXR",
        "double": "RTMINI_DOUBLE",
        "benchmarks": "RTMINI_ENABLE_BENCHMARKS",
    }
    # Variants that pick the Kokkos backend: rtmini has no option of its own for them, it
    # builds for whatever backends the Kokkos it finds has (cuda comes from CudaPackage).
    kokkos_backend_variants = ("cuda", "openmp")

    variant("mpi", default=True, description="MPI ranks (off: a one-rank stand-in)")
    variant("hdf5", default=True, description="per-rank timings and checkpoints in HDF5")
    variant("png", default=True, description="PNG image output")
    variant("exr", default=True, description="OpenEXR image output and AOV layers")
    variant("double", default=False, description="double-precision geometry and radiance")
    variant("benchmarks", default=False, description="rtmini-bvh-bench and other benchmarks")
    variant("openmp", default=True, description="Kokkos OpenMP backend on the host")

    depends_on("cmake@3.16:", type="build")
    depends_on("kokkos@3.4:")
    depends_on("kokkos+openmp", when="+openmp")
    depends_on("kokkos+cuda+cuda_lambda+wrapper", when="+cuda")
    for _arch in CudaPackage.cuda_arch_values:
        depends_on(f"kokkos cuda_arch={_arch}", when=f"+cuda cuda_arch={_arch}")
    depends_on("mpi", when="+mpi")
    depends_on("hdf5~mpi", when="+hdf5~mpi")
    depends_on("hdf5+mpi", when="+hdf5+mpi")
    depends_on("xxhash", when="+hdf5")  # checksum per HDF5 dataset (header only)
    depends_on("libpng", when="+png")
    depends_on("openexr@3:", when="+exr")
    depends_on("cli11")
    depends_on("tomlplusplus")
    depends_on("nlohmann-json")
    depends_on("tinyobjloader")
    depends_on("random123")
    depends_on("eigen")
    depends_on("googletest", type="test")

    def cmake_args(self):
        args = [self.define_from_variant(option, name) for name, option in self.variant_options.items()]
        args += [
            self.define("RTMINI_ENABLE_TESTS", self.run_tests),
            self.define("RTMINI_ENABLE_EMBREE_PEER", False),
            # Compute nodes may differ from the build node: the compiler's default target.
            self.define("RTMINI_HOST_ARCH", ""),
            self.define("Kokkos_ROOT", self.spec["kokkos"].prefix),
        ]
        if self.spec.satisfies("+cuda"):
            # Kokkos' launcher sends Kokkos targets through nvcc_wrapper; the host compiler
            # builds the rest (toml++ cannot go through nvcc). See docs/cuda.md.
            args.append(self.define("CMAKE_CXX_COMPILER", self.compiler.cxx))
        return args
