// A C++ host: a small RAII wrapper over libfractum that throws on errors, driving the SHPB
// specimen at a constant incident-face speed, then a reduced beam2d scene to its end (where
// the SHPB calls throw with FRACTUM_ERR_MODEL).
//
// Build (from the repository root, after `cargo build --release -p fractum-ffi`):
//   g++ -std=c++17 -Wall -Wextra -Iinclude ffi/examples/host.cpp -Ltarget/release -lfractum
//       -Wl,-rpath,$PWD/target/release -o host_cpp      (one command line)
//   ./host_cpp scenes/shpb_sand.toml
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "fractum.h"

namespace fractum {

struct Error : std::runtime_error {
    FractumStatus status;
    Error(FractumStatus s, const std::string &what) : std::runtime_error(what), status(s) {}
};

inline void check(FractumStatus s) {
    if (s != FRACTUM_OK) throw Error(s, fractum_last_error());
}

// Owns one simulation; freed when the object goes out of scope.
class Simulation {
  public:
    Simulation(const std::string &scene, const std::vector<std::string> &overrides, int threads = 1) {
        std::vector<const char *> args;
        for (const auto &o : overrides) args.push_back(o.c_str());
        check(fractum_create_from_file(scene.c_str(), args.data(), args.size(), threads, &handle_));
    }
    ~Simulation() { fractum_free(handle_); }
    Simulation(const Simulation &) = delete;
    Simulation &operator=(const Simulation &) = delete;

    std::string model() const {
        const char *kind = nullptr;
        check(fractum_model(handle_, &kind));
        return kind;
    }
    bool finished() const {
        int32_t f = 0;
        check(fractum_finished(handle_, &f));
        return f != 0;
    }
    double scalar(const std::string &column) const {
        double v;
        check(fractum_scalar(handle_, column.c_str(), &v));
        return v;
    }
    // The summary as JSON text (summary.json's keys but wall_seconds).
    std::string summary_json() const {
        size_t needed = 0;
        FractumStatus s = fractum_summary_json(handle_, nullptr, 0, &needed);
        if (s != FRACTUM_ERR_BUFFER) check(s);
        std::string text(needed, '\0');
        check(fractum_summary_json(handle_, text.data(), text.size(), &needed));
        text.resize(needed - 1);
        return text;
    }
    void set_face_speeds(double top, double bottom) { check(fractum_set_face_speeds(handle_, top, bottom)); }
    void advance(uint64_t steps) { check(fractum_advance(handle_, steps)); }
    void advance_to(double t) { check(fractum_advance_to(handle_, t)); }
    std::pair<double, double> stresses() const {
        double top, bottom, area;
        check(fractum_face_stresses(handle_, &top, &bottom, &area));
        return {top, bottom};
    }
    double strain() const {
        double t, s;
        uint64_t n;
        check(fractum_progress(handle_, &t, &s, &n));
        return s;
    }
    std::vector<double> radii() const {
        uint64_t bodies, contacts;
        double ke;
        check(fractum_counts(handle_, &bodies, &contacts, &ke));
        std::vector<double> r(bodies);
        check(fractum_copy_radii(handle_, r.data(), r.size()));
        return r;
    }

  private:
    FractumHandle handle_ = 0;
};

}  // namespace fractum

int main(int argc, char **argv) {
    const std::string scene = argc > 1 ? argv[1] : "scenes/shpb_sand.toml";
    try {
        fractum::Simulation sim(scene, {"output.vtk=0", "output.every=1000000"});
        auto radii = sim.radii();
        std::printf("%zu grains, first radius %.4e m\n", radii.size(), radii[0]);
        sim.set_face_speeds(3.0, 0.0);
        double previous = 0.0;
        for (int k = 1; k <= 10; k++) {
            sim.advance_to(1e-5 * k);
            auto [top, bottom] = sim.stresses();
            std::printf("strain %.4f  stress top %.4e Pa  bottom %.4e Pa\n", sim.strain(), top, bottom);
            if (k > 2 && top <= previous) throw std::runtime_error("the stress should rise with strain");
            previous = top;
        }
        try {
            fractum::Simulation bad(scene, {"material.young=-1"});
            throw std::runtime_error("a negative Young's modulus was accepted");
        } catch (const fractum::Error &e) {
            if (e.status != FRACTUM_ERR_INPUT) throw;
            std::printf("refused as expected: %s\n", e.what());
        }

        // Any model runs through the same calls; the SHPB ones throw on a model without faces.
        fractum::Simulation beams("scenes/beam2d_moduli.toml",
                                  {"sample.cells=[8, 12]", "loading.strain_rate=0.4", "loading.ramp_time=0.001"});
        if (beams.model() != "beam2d") throw std::runtime_error("beam2d_moduli is a beam2d scene");
        try {
            beams.set_face_speeds(3.0, 0.0);
            throw std::runtime_error("face speeds were accepted on a beam2d run");
        } catch (const fractum::Error &e) {
            if (e.status != FRACTUM_ERR_MODEL) throw;
            std::printf("refused as expected: %s\n", e.what());
        }
        while (!beams.finished()) beams.advance(1000);
        std::string summary = beams.summary_json();
        if (summary.find("\"model\": \"beam2d\"") == std::string::npos)
            throw std::runtime_error("the summary names the model: " + summary);
        std::printf("beam2d: stress %.4e Pa at strain %.5f, summary of %zu bytes\n", beams.scalar("stress"),
                    beams.scalar("strain"), summary.size());
    } catch (const std::exception &e) {
        std::fprintf(stderr, "host.cpp: FAILED: %s\n", e.what());
        return 1;
    }
    std::printf("host.cpp: ok\n");
    return 0;
}
