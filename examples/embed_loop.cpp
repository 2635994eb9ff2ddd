// Embedding tumble in an application's own loop, the way a game or a DCC tool would: the
// application owns the frame clock, advances the simulation to each frame time, and reads
// the poses to draw. Here a crate is knocked off a table edge onto the floor.
//
// Checks (exit 1 if one fails): the crate ends at rest on the floor (its centre 0.15 m up,
// less the contact's 1 mm), having left the table; L and energy stay finite throughout.
#include <tumble/tumble.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

namespace
{

struct SceneDeleter {
    void operator()(tb_scene *s) const { tb_scene_destroy(s); }
};
struct IntegratorDeleter {
    void operator()(tb_integrator *i) const { tb_integrator_destroy(i); }
};

// What a renderer would take each frame: where the model goes.
struct Pose {
    std::array<double, 3> position;
    std::array<double, 4> orientation;
};

Pose pose_of(const tb_scene *scene, size_t id)
{
    Pose pose{};
    tb_scene_body_shape_pose(scene, tb_scene_states_const(scene), id, pose.position.data(),
                             pose.orientation.data());
    return pose;
}

} // namespace

int main()
{
    tb_scene_def scene_def = tb_scene_def_default();
    tb_scene *raw_scene = nullptr;
    if (tb_scene_create(&scene_def, &raw_scene, nullptr) != TB_STATUS_OK) {
        return 1;
    }
    std::unique_ptr<tb_scene, SceneDeleter> scene(raw_scene);

    const double size[3] = {0.3, 0.3, 0.3};
    tb_body_def crate = tb_body_def_default();
    crate.name = "crate";
    tb_mass_from_box(TB_MASS_DENSITY, 300.0, size, &crate.mass, nullptr);
    crate.position[2] = 1.0 + 0.15; // on a 1 m table...
    crate.velocity[0] = 1.5;        // ...pushed towards its edge at x = 0.3
    size_t id = 0;
    tb_contact_point corners[8];
    size_t count = 0;
    tb_contact_points_box(size, corners, 8, &count);
    if (tb_scene_add_body(scene.get(), &crate, &id) != TB_STATUS_OK ||
        tb_scene_set_contact_points(scene.get(), id, corners, count, 4) != TB_STATUS_OK) {
        std::fprintf(stderr, "%s\n", tb_scene_detail(scene.get()));
        return 1;
    }
    const double g[3] = {0, 0, -9.81};
    tb_scene_add_gravity(scene.get(), g);
    tb_ground_def floor = tb_ground_def_default();
    tb_scene_add_ground(scene.get(), &floor);
    // The table top (z = 1 for x < 0.3) is the application's own effect, a user callback: a
    // penalty push on the crate's corners that are over the table and dip below its surface.
    tb_scene_add_user_effect(
        scene.get(),
        [](double, const tb_scene *s, const double *y, double *dydt, void *) {
            for (unsigned c = 0; c < 8; ++c) {
                double R[9];
                tb_scene_body_rotation(s, y, 0, R);
                const double r[3] = {(c & 1 ? 0.15 : -0.15), (c & 2 ? 0.15 : -0.15),
                                     (c & 4 ? 0.15 : -0.15)};
                double p[3];
                for (int i = 0; i < 3; ++i) {
                    p[i] = y[i] + R[3 * i] * r[0] + R[3 * i + 1] * r[1] + R[3 * i + 2] * r[2];
                }
                const double depth = 1.0 - p[2];
                if (p[0] < 0.3 && depth > 0 && depth < 0.05) {
                    double v[3];
                    tb_scene_body_velocity(s, y, 0, v);
                    const double push[3] = {-2.0 * v[0], 0, 2.0e5 * depth - 500.0 * v[2]};
                    tb_effect_add_force(s, y, dydt, 0, push, p);
                }
            }
            return 0;
        },
        nullptr);

    tb_integrator_def how = tb_integrator_def_default(); // RK4 at 1/240 s
    how.dt = 0.0; // the scene's default step: ground contact is stiff (tb_scene_default_step)
    tb_integrator *raw_integrator = nullptr;
    if (tb_scene_integrator_create(scene.get(), &how, 0.0, &raw_integrator) != TB_STATUS_OK) {
        std::fprintf(stderr, "%s\n", tb_scene_detail(scene.get()));
        return 1;
    }
    std::unique_ptr<tb_integrator, IntegratorDeleter> integrator(raw_integrator);

    const double fps = 60.0;
    bool left_table = false, finite = true;
    Pose pose{};
    for (int frame = 1; frame <= 4 * 60; ++frame) { // the application's loop
        if (tb_integrator_advance(integrator.get(), frame / fps) != TB_STATUS_OK) {
            std::fprintf(stderr, "%s\n", tb_integrator_detail(integrator.get()));
            return 1;
        }
        pose = pose_of(scene.get(), id); // ... hand to the renderer ...
        left_table = left_table || pose.position[2] < 0.9;
        for (double x : pose.position) {
            finite = finite && std::isfinite(x);
        }
        if (frame % 30 == 0) {
            std::printf("t = %.1f s  crate at (%.3f, %.3f, %.3f)\n", frame / fps, pose.position[0],
                        pose.position[1], pose.position[2]);
        }
    }
    double v[3];
    tb_scene_body_velocity(scene.get(), tb_scene_states(scene.get()), id, v);
    const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const bool resting = std::fabs(pose.position[2] - (0.15 - 0.001)) < 0.02 && speed < 1e-2;
    std::printf("checks: left the table %s, rests on the floor %s (speed %.2g m/s), finite %s\n",
                left_table ? "yes" : "NO", resting ? "yes" : "NO", speed, finite ? "yes" : "NO");
    return left_table && resting && finite ? 0 : 1;
}
