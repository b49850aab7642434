// The manifest's "world" (schema 1.4: the project's medium, water, step settings and the
// body's start) and the water models it names (runtime.hpp, WaterModel; the formulas are the
// evaluation core's plimsoll_eval/water.hpp).
#include "world.hpp"

#include "plimsoll_eval/water.hpp"

#include <cmath>

namespace plimsoll_runtime {

namespace ev = plimsoll_eval;

namespace {

ev::WaterModelDesc describe(const WaterModel& w) {
    ev::WaterModelDesc d;
    d.kind = w.kind == WaterModel::Kind::Flat       ? ev::WaterModelDesc::Kind::Flat
             : w.kind == WaterModel::Kind::Gerstner ? ev::WaterModelDesc::Kind::Gerstner
                                                    : ev::WaterModelDesc::Kind::HeightGrid;
    d.level = w.level;
    d.gravity = w.gravity;
    for (const WaterModel::Wave& v : w.waves)
        d.waves.push_back(
            {v.amplitude, v.wavelength, v.direction[0], v.direction[1], v.steepness, v.phase});
    d.grid.countX = w.countX;
    d.grid.countZ = w.countZ;
    d.grid.spacing = w.spacing;
    d.grid.originX = w.originX;
    d.grid.originZ = w.originZ;
    d.grid.heights = w.heights;
    return d;
}

/// A reader of one object's members that stops at the first problem, naming its JSON path.
class Members {
public:
    Members(const std::string& file, std::string& error) : file_(file), error_(error) {}
    bool fail(const std::string& at, const std::string& what) {
        error_ = file_ + ": " + at + ": " + what;
        return false;
    }
    bool number(const json::Value& o, const std::string& at, const char* key, double& out,
                bool required = true) {
        const json::Value* v = o.find(key);
        if (!v) return !required || fail(at + "." + key, "missing");
        if (!v->isNumber() || !std::isfinite(v->number))
            return fail(at + "." + key, "expected a finite number");
        out = v->number;
        return true;
    }
    bool numbers(const json::Value& o, const std::string& at, const char* key, double* out,
                 std::size_t n) {
        const json::Value* v = o.find(key);
        if (!v) return fail(at + "." + key, "missing");
        if (!v->isArray() || v->array.size() != n)
            return fail(at + "." + key, "expected " + std::to_string(n) + " numbers");
        for (std::size_t i = 0; i < n; ++i) {
            if (!v->array[i].isNumber() || !std::isfinite(v->array[i].number))
                return fail(at + "." + key, "expected " + std::to_string(n) + " finite numbers");
            out[i] = v->array[i].number;
        }
        return true;
    }
    bool vec3(const json::Value& o, const std::string& at, const char* key, Vec3& out) {
        double v[3];
        if (!numbers(o, at, key, v, 3)) return false;
        out = {v[0], v[1], v[2]};
        return true;
    }
    const json::Value* object(const json::Value& o, const std::string& at, const char* key) {
        const json::Value* v = o.find(key);
        if (!v || !v->isObject()) {
            fail(at + "." + key, v ? "expected an object" : "missing");
            return nullptr;
        }
        return v;
    }

private:
    std::string file_;
    std::string& error_;
};

/// The grid of a height_grid water: bounded by format limits before anything is allocated.
bool readGrid(Members& r, const json::Value& g, const std::string& at, WaterModel& w) {
    double cx = 0, cz = 0, origin[2] = {0, 0};
    if (!r.number(g, at, "count_x", cx) || !r.number(g, at, "count_z", cz) ||
        !r.number(g, at, "spacing", w.spacing) || !r.numbers(g, at, "origin", origin, 2))
        return false;
    constexpr double kMaxSide = 8192;
    if (cx != std::floor(cx) || cz != std::floor(cz) || cx < 1 || cz < 1 || cx > kMaxSide ||
        cz > kMaxSide)
        return r.fail(at, "count_x and count_z must be integers in 1..8192");
    if (!(w.spacing > 0)) return r.fail(at + ".spacing", "must be > 0");
    w.countX = static_cast<int>(cx);
    w.countZ = static_cast<int>(cz);
    w.originX = origin[0];
    w.originZ = origin[1];
    const json::Value* h = g.find("heights");
    const std::size_t count =
        static_cast<std::size_t>(w.countX) * static_cast<std::size_t>(w.countZ);
    if (!h || !h->isArray() || h->array.size() != count)
        return r.fail(at + ".heights",
                      "expected count_x * count_z = " + std::to_string(count) + " numbers");
    w.heights.reserve(count);
    for (const json::Value& v : h->array) {
        if (!v.isNumber() || !std::isfinite(v.number))
            return r.fail(at + ".heights", "expected finite numbers");
        w.heights.push_back(static_cast<float>(v.number));
    }
    return true;
}

bool readWater(Members& r, const json::Value& o, const std::string& at, WaterModel& w) {
    const json::Value* model = o.find("model");
    if (!model || !model->isString())
        return r.fail(at + ".model", "expected \"flat\", \"gerstner\" or \"height_grid\"");
    if (!r.number(o, at, "level", w.level)) return false;
    if (model->string == "flat") {
        w.kind = WaterModel::Kind::Flat;
    } else if (model->string == "gerstner") {
        w.kind = WaterModel::Kind::Gerstner;
        const json::Value* waves = o.find("waves");
        if (!waves || !waves->isArray()) return r.fail(at + ".waves", "expected an array");
        constexpr std::size_t kMaxWaves = 64;
        if (waves->array.size() > kMaxWaves) return r.fail(at + ".waves", "more than 64 waves");
        for (std::size_t i = 0; i < waves->array.size(); ++i) {
            const json::Value& v = waves->array[i];
            const std::string wat = at + ".waves[" + std::to_string(i) + "]";
            if (!v.isObject()) return r.fail(wat, "expected an object");
            WaterModel::Wave wave;
            if (!r.number(v, wat, "amplitude", wave.amplitude) ||
                !r.number(v, wat, "wavelength", wave.wavelength) ||
                !r.numbers(v, wat, "direction", wave.direction, 2) ||
                !r.number(v, wat, "steepness", wave.steepness) ||
                !r.number(v, wat, "phase", wave.phase))
                return false;
            if (!(wave.wavelength > 0)) return r.fail(wat + ".wavelength", "must be > 0");
            w.waves.push_back(wave);
        }
    } else if (model->string == "height_grid") {
        w.kind = WaterModel::Kind::HeightGrid;
        const json::Value* grid = r.object(o, at, "grid");
        if (!grid || !readGrid(r, *grid, at + ".grid", w)) return false;
    } else {
        return r.fail(at + ".model",
                      "unknown \"" + model->string + "\" (flat, gerstner, height_grid)");
    }
    return true;
}

bool readStart(Members& r, const json::Value& o, const std::string& at, BundleWorld& out) {
    double q[4];
    if (!r.vec3(o, at, "position", out.startPose.position) ||
        !r.numbers(o, at, "orientation_wxyz", q, 4) ||
        !r.vec3(o, at, "velocity", out.startVelocity.linear) ||
        !r.vec3(o, at, "angular_velocity", out.startVelocity.angular))
        return false;
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (!(std::abs(n - 1.0) < 1e-6))
        return r.fail(at + ".orientation_wxyz", "not a unit quaternion");
    out.startPose.orientation = {q[0], q[1], q[2], q[3]};
    return true;
}

}  // namespace

namespace {

/// The model's wave terms (no allocation for up to 16 waves).
ev::WaveTable waveTable(const WaterModel& w) {
    return ev::WaveTable(w.waves, w.gravity, [](const WaterModel::Wave& v, double& x, double& z) {
        x = v.direction[0];
        z = v.direction[1];
    });
}

}  // namespace

double WaterModel::height(double x, double z, double time) const {
    switch (kind) {
        case Kind::Flat:
            return level;
        case Kind::HeightGrid:
            return level + ev::water_detail::gridHeight(heights.data(), countX, countZ, spacing,
                                                        originX, originZ, x, z);
        case Kind::Gerstner: {
            const ev::WaveTable terms = waveTable(*this);
            return ev::water_detail::gerstnerHeight(terms.data(), terms.size(), level, x, z, time);
        }
    }
    return level;
}

Vec3 WaterModel::velocity(const Vec3& p, double time) const {
    if (kind != Kind::Gerstner) return {0, 0, 0};
    const ev::WaveTable terms = waveTable(*this);
    double out[3];
    ev::water_detail::gerstnerVelocity(terms.data(), terms.size(), level, p.x, p.y, p.z, time, out);
    return {out[0], out[1], out[2]};
}

double WaterModel::maxHeight() const { return ev::waterMaxHeight(describe(*this)); }
double WaterModel::minHeight() const { return ev::waterMinHeight(describe(*this)); }

Water WaterModel::water() const {
    Water w;
    w.level = level;
    if (kind == Kind::Flat) return w;
    // The model's constants once, shared by the callbacks (which may run on several threads:
    // they only read them).
    auto d = std::make_shared<const ev::WaterModelDesc>(describe(*this));
    auto terms =
        std::make_shared<const std::vector<ev::water_detail::WaveTerms>>(ev::waveTerms(*d));
    w.height = [d, terms](double x, double z, double t) {
        return ev::waterHeight(*d, *terms, x, z, t);
    };
    w.heights = [d, terms](std::size_t n, const double* x, const double* z, double t, double* out) {
        for (std::size_t i = 0; i < n; ++i) out[i] = ev::waterHeight(*d, *terms, x[i], z[i], t);
    };
    if (kind == Kind::Gerstner) {
        w.velocity = [d, terms](const Vec3& p, double t) {
            double out[3];
            ev::waterVelocity(*d, *terms, p.x, p.y, p.z, t, out);
            return Vec3{out[0], out[1], out[2]};
        };
        w.velocities = [d, terms](std::size_t n, const double* x, const double* y, const double* z,
                                  double t, double* out) {
            for (std::size_t i = 0; i < n; ++i)
                ev::waterVelocity(*d, *terms, x[i], y[i], z[i], t, out + 3 * i);
        };
    }
    w.minHeight = ev::waterMinHeight(*d);
    w.maxHeight = ev::waterMaxHeight(*d);
    return w;
}

bool readBundleWorld(const json::Value& manifest, const std::string& file, BundleWorld& out,
                     std::string& error) {
    const json::Value* world = manifest.find("world");
    if (!world || world->isNull()) return true;  // a bundle before 1.4: the defaults
    Members r(file, error);
    const std::string at = "$.world";
    if (!world->isObject()) return r.fail(at, "expected an object");
    const json::Value* medium = r.object(*world, at, "medium");
    if (!medium || !r.number(*medium, at + ".medium", "density", out.density) ||
        !r.number(*medium, at + ".medium", "viscosity", out.viscosity))
        return false;
    if (!(out.density > 0) || !(out.viscosity >= 0))
        return r.fail(at + ".medium", "density must be > 0, viscosity >= 0");
    if (!r.vec3(*world, at, "gravity", out.gravity)) return false;
    const json::Value* water = r.object(*world, at, "water");
    if (!water || !readWater(r, *water, at + ".water", out.water)) return false;
    out.water.gravity = norm(out.gravity);
    const json::Value* sim = r.object(*world, at, "simulation");
    double subSteps = 0;
    if (!sim || !r.number(*sim, at + ".simulation", "time_step", out.timeStep) ||
        !r.number(*sim, at + ".simulation", "sub_steps", subSteps) ||
        !r.number(*sim, at + ".simulation", "max_phase_step", out.maxPhaseStep))
        return false;
    if (!(out.timeStep > 0) || subSteps != std::floor(subSteps) || subSteps < 1 ||
        subSteps > 1000 || !(out.maxPhaseStep > 0))
        return r.fail(at + ".simulation",
                      "time_step and max_phase_step must be > 0, sub_steps in 1..1000");
    out.subSteps = static_cast<int>(subSteps);
    if (const json::Value* integrator = sim->find("integrator");
        integrator && integrator->isString())
        out.integrator = integrator->string;
    if (const json::Value* sleep = sim->find("sleep"); sleep && !sleep->isNull()) {
        const std::string path = at + ".simulation.sleep";
        BundleWorld::Sleep& s = out.sleep;
        if (!sleep->isObject()) return r.fail(path, "expected an object");
        const json::Value* enabled = sleep->find("enabled");
        if (!enabled || !enabled->isBool())
            return r.fail(path + ".enabled", "expected true or false");
        s.enabled = enabled->boolean;
        if (!r.number(*sleep, path, "linear_speed", s.linearSpeed) ||
            !r.number(*sleep, path, "angular_speed", s.angularSpeed) ||
            !r.number(*sleep, path, "linear_acceleration", s.linearAcceleration) ||
            !r.number(*sleep, path, "angular_acceleration", s.angularAcceleration) ||
            !r.number(*sleep, path, "rest_time", s.restTime) ||
            !r.number(*sleep, path, "wake_height", s.wakeHeight))
            return false;
        if (s.linearSpeed < 0 || s.angularSpeed < 0 || s.linearAcceleration < 0 ||
            s.angularAcceleration < 0 || s.restTime < 0 || s.wakeHeight < 0)
            return r.fail(path, "the thresholds must be >= 0");
    }
    const json::Value* start = r.object(*world, at, "start");
    if (!start || !readStart(r, *start, at + ".start", out)) return false;
    out.present = true;
    return true;
}

}  // namespace plimsoll_runtime
