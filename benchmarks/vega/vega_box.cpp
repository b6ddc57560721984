// Vega FEM on the bench_box scenes, for the side-by-side figure of issue 18 item 4 (docs/perf.md
// "Against Vega FEM, side by side"). Not part of polycut's build: benchmarks/vega/build.sh
// compiles it against a VegaFEM checkout (VEGA_ROOT), with Vega's hard-coded PCG tolerance of
// its implicit Euler integrator made a variable (vega_pcg_tolerance) so that it can be loosened
// to the accuracy criterion, as polycut's is.
//
//   vega_box N TOL [--steps S] [--warmup W]
//
// The problem of assets/scenes/bench_boxN.json: a 0.1 m cube of N^3 blocks, each split into 6
// Kuhn tets around its main diagonal, E = 10 kPa, nu = 0.45, rho = 1000 kg/m^3, Rayleigh
// stiffness damping 0.01 s, the x = 0 face fixed, gravity -9.81 m/s^2 along z, dt = 0.01 s.
// Vega's way: corotational linear FEM (warp 1: stiffness warping, as polycut's corotated
// model), consistent mass matrix, ImplicitBackwardEulerSparse with one Newton iteration per step
// (linearized once per step, as polycut), Jacobi-preconditioned CG from zero, one thread.
// Output (one JSON line): CPU and wall ms per step over S steps after W warm-up steps from rest
// (median, p99), and err = ||x_50 - x_50,ref|| / ||x_50,ref - X|| after 50 steps against the
// same run at PCG tolerance 1e-12 (docs/perf.md's criterion: err <= 1e-3).
#include "corotationalLinearFEM.h"
#include "corotationalLinearFEMForceModel.h"
#include "generateMassMatrix.h"
#include "implicitBackwardEulerSparse.h"
#include "tetMesh.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

double vega_pcg_tolerance = 1e-6; // read by the patched implicitBackwardEulerSparse.cpp

namespace {

constexpr int kAccuracyStep = 50;

struct Box {
    std::vector<double> vertices; // 3 per node [m]
    std::vector<int> tets; // 4 per tet, positively oriented
    std::vector<int> fixed_dofs; // sorted
};

Box kuhn_box(int n) {
    Box b;
    const double h = 0.1 / n;
    const auto id = [n](int i, int j, int k) { return (k * (n + 1) + j) * (n + 1) + i; };
    for (int k = 0; k <= n; ++k)
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                b.vertices.insert(b.vertices.end(), { i * h, j * h, k * h });
                if (i == 0)
                    for (int a = 0; a < 3; ++a)
                        b.fixed_dofs.push_back(3 * id(i, j, k) + a);
            }
    std::sort(b.fixed_dofs.begin(), b.fixed_dofs.end());
    // Block corners c0..c7 (c0 = (0,0,0), c6 = (1,1,1)); the six tets around the diagonal c0-c6
    // are the monotone lattice paths from c0 to c6.
    const int paths[6][3]
        = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };
    for (int k = 0; k < n; ++k)
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i)
                for (const auto& p : paths) {
                    int c[3] = { i, j, k };
                    int t[4];
                    t[0] = id(c[0], c[1], c[2]);
                    for (int s = 0; s < 3; ++s) {
                        ++c[p[s]];
                        t[s + 1] = id(c[0], c[1], c[2]);
                    }
                    const double* x0 = &b.vertices[3 * t[0]];
                    double e[3][3];
                    for (int s = 0; s < 3; ++s)
                        for (int a = 0; a < 3; ++a)
                            e[s][a] = b.vertices[3 * t[s + 1] + a] - x0[a];
                    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
                        - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
                        + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
                    if (det < 0)
                        std::swap(t[2], t[3]);
                    b.tets.insert(b.tets.end(), t, t + 4);
                }
    return b;
}

double cpu_ms() {
    timespec t {};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

double percentile(std::vector<double> v, double p) {
    if (v.empty())
        return 0;
    std::sort(v.begin(), v.end());
    const double r = p / 100.0 * double(v.size() - 1);
    const std::size_t lo = std::size_t(r);
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (r - double(lo)) * (v[hi] - v[lo]);
}

struct Run {
    std::vector<double> q50; // displacements after step 50 [m]
    std::vector<double> cpu, wall; // per timed step [ms]
};

Run simulate(const Box& box, double tol, int warmup, int steps) {
    vega_pcg_tolerance = tol;
    std::vector<double> vertices = box.vertices;
    std::vector<int> tets = box.tets;
    TetMesh mesh(int(vertices.size() / 3), vertices.data(), int(tets.size() / 4), tets.data(), 1e4,
        0.45, 1000.0);
    CorotationalLinearFEM fem(&mesh);
    CorotationalLinearFEMForceModel model(&fem, 1);
    SparseMatrix* mass = nullptr;
    GenerateMassMatrix::computeMassMatrix(&mesh, &mass, true);
    const int r = 3 * mesh.getNumVertices();
    std::vector<int> fixed = box.fixed_dofs;
    ImplicitBackwardEulerSparse integrator(
        r, 0.01, mass, &model, int(fixed.size()), fixed.data(), 0.0, 0.01, 1, 1e-6, 1);
    std::vector<double> g(r, 0.0), f(r, 0.0);
    for (int i = 0; i < r; i += 3)
        g[i + 2] = -9.81;
    mass->MultiplyVector(g.data(), f.data());
    for (int d : fixed)
        f[d] = 0;
    integrator.SetExternalForces(f.data());
    Run run;
    for (int k = 1; k <= warmup + steps; ++k) {
        const double c0 = cpu_ms();
        const auto w0 = std::chrono::steady_clock::now();
        if (integrator.DoTimestep() != 0) {
            std::fprintf(stderr, "vega_box: DoTimestep failed at step %d\n", k);
            std::exit(1);
        }
        const double w
            = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - w0)
                  .count();
        const double c = cpu_ms() - c0;
        if (k == kAccuracyStep)
            run.q50.assign(integrator.Getq(), integrator.Getq() + r);
        if (k > warmup) {
            run.cpu.push_back(c);
            run.wall.push_back(w);
        }
    }
    delete mass;
    return run;
}

} // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: vega_box N TOL [--steps S] [--warmup W]\n");
        return 2;
    }
    const int n = std::atoi(argv[1]);
    const double tol = std::atof(argv[2]);
    int steps = 50, warmup = 10;
    for (int i = 3; i + 1 < argc; i += 2) {
        const std::string s = argv[i];
        if (s == "--steps")
            steps = std::atoi(argv[i + 1]);
        else if (s == "--warmup")
            warmup = std::atoi(argv[i + 1]);
    }
    const Box box = kuhn_box(n);
    const Run ref = simulate(box, 1e-12, kAccuracyStep, 0);
    const Run run = simulate(box, tol, warmup, std::max(steps, kAccuracyStep - warmup));
    double e = 0, u = 0;
    for (std::size_t i = 0; i < ref.q50.size(); ++i) {
        e += (run.q50[i] - ref.q50[i]) * (run.q50[i] - ref.q50[i]);
        u += ref.q50[i] * ref.q50[i];
    }
    double load = -1;
    if (FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fscanf(f, "%lf", &load) != 1)
            load = -1;
        std::fclose(f);
    }
    std::printf("{\"code\": \"vega\", \"box\": %d, \"nodes\": %zu, \"tets\": %zu, \"tol\": %g, "
                "\"steps\": %zu, \"cpu_ms\": {\"median\": %.3f, \"p99\": %.3f}, "
                "\"wall_ms\": {\"median\": %.3f, \"p99\": %.3f}, \"err\": %.3g, \"load\": %.2f}\n",
        n, box.vertices.size() / 3, box.tets.size() / 4, tol, run.cpu.size(),
        percentile(run.cpu, 50), percentile(run.cpu, 99), percentile(run.wall, 50),
        percentile(run.wall, 99), u > 0 ? std::sqrt(e / u) : -1.0, load);
    return 0;
}
