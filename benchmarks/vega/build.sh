#!/bin/bash
# Builds benchmarks/vega/vega_box against a VegaFEM checkout (not part of polycut's build; see
# vega_box.cpp and docs/perf.md "Against Vega FEM, side by side").
#
#   VEGA_ROOT=/path/to/VegaFEM benchmarks/vega/build.sh [OUT_DIR]
#
# Compiles the Vega libraries the driver needs with the flags of polycut's release build
# (-O2, no -march), one thread, Vega's Jacobi-PCG solver. Vega's implicit Euler integrator
# hard-codes its PCG tolerance (1e-6): the copy compiled here reads it from the driver's
# variable vega_pcg_tolerance instead, the only change to Vega's code.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
: "${VEGA_ROOT:?set VEGA_ROOT to a VegaFEM checkout (https://github.com/dyollb/VegaFEM)}"
lib="$VEGA_ROOT/libraries"
out=${1:-$here/../../build/vega}
mkdir -p "$out/src"
dirs="minivector sparseMatrix sparseSolver volumetricMesh corotationalLinearFEM elasticForceModel
      forceModel integrator integratorSparse constrainedDOFs performanceCounter polarDecomposition
      basicAlgorithms matrixIO include mesh"
inc=""
for d in $dirs; do inc="$inc -I$lib/$d"; done
sources="minivector/vec3d.cpp minivector/mat3d.cpp minivector/eig3.cpp minivector/vec3i.cpp
         minivector/vec4i.cpp minivector/vec2d.cpp minivector/vec3.cpp
         sparseMatrix/sparseMatrix.cpp sparseSolver/CGSolver.cpp sparseSolver/linearSolver.cpp
         volumetricMesh/volumetricMesh.cpp volumetricMesh/tetMesh.cpp
         volumetricMesh/generateMassMatrix.cpp volumetricMesh/volumetricMeshENuMaterial.cpp
         volumetricMesh/volumetricMeshOrthotropicMaterial.cpp
         volumetricMesh/volumetricMeshMooneyRivlinMaterial.cpp
         volumetricMesh/volumetricMeshParser.cpp volumetricMesh/volumetricMeshLoader.cpp
         volumetricMesh/cubicMesh.cpp
         corotationalLinearFEM/corotationalLinearFEM.cpp
         elasticForceModel/corotationalLinearFEMForceModel.cpp forceModel/forceModel.cpp
         integrator/integratorBase.cpp integratorSparse/integratorBaseSparse.cpp
         integratorSparse/implicitNewmarkSparse.cpp constrainedDOFs/constrainedDOFs.cpp
         polarDecomposition/polarDecomposition.cpp polarDecomposition/polarDecompositionGradient.cpp
         mesh/boundingBox.cpp mesh/geometryQuery.cpp"
# the integrator with its PCG tolerance read from the driver
sed -e 's/SolveLinearSystemWithJacobiPreconditioner(buffer, bufferConstrained, 1e-6, 10000)/SolveLinearSystemWithJacobiPreconditioner(buffer, bufferConstrained, vega_pcg_tolerance, 10000)/' \
    -e 's/#include "implicitBackwardEulerSparse.h"/#include "implicitBackwardEulerSparse.h"\nextern double vega_pcg_tolerance;/' \
    "$lib/integratorSparse/implicitBackwardEulerSparse.cpp" > "$out/src/implicitBackwardEulerSparse.cpp"
grep -q "vega_pcg_tolerance, 10000" "$out/src/implicitBackwardEulerSparse.cpp" \
    || { echo "build.sh: Vega's PCG call was not found; the patch does not apply" >&2; exit 1; }
# vega-config.h as Vega's CMake writes it with every option off (no TBB, MKL, PARDISO, SPOOLES)
sed -e 's|^#cmakedefine \(.*\)|/* #undef \1 */|' "$lib/include/vega-config.h.in" > "$out/src/vega-config.h"
inc="$inc -I$out/src"
flags="-O2 -DNDEBUG -std=c++14 -w"
objs=""
for s in $sources "$out/src/implicitBackwardEulerSparse.cpp" "$here/vega_box.cpp"; do
    case $s in /*) src=$s ;; *) src=$lib/$s ;; esac
    o="$out/src/$(basename "${src%.cpp}").o"
    if [ ! -f "$o" ] || [ "$src" -nt "$o" ]; then
        g++ $flags $inc -c "$src" -o "$o"
    fi
    objs="$objs $o"
done
# boundingBox.cpp has an OpenGL render(): OSMesa (polycut's renderer) provides the symbols
g++ -o "$out/vega_box" $objs -lOSMesa -lpthread
echo "$out/vega_box"
