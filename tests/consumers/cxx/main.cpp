// A C++17 program using the installed tumble: loads a scene from JSON, runs it with a
// capturing callback, and checks the ball fell as g t^2 / 2 says.
#include <tumble/tumble.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

int main()
{
    const char *json = R"({"bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1},
                           "mass": 1, "position": [0, 0, 10]}],
                           "effects": [{"type": "gravity"}],
                           "output": {"fps": 10, "duration": 1}})";
    tb_scene *raw = nullptr;
    tb_run_def run;
    tb_error error;
    if (tb_scene_load_string(json, "inline.json", nullptr, &raw, &run, &error) != TB_STATUS_OK) {
        std::fprintf(stderr, "%s\n", error.message);
        return 1;
    }
    std::unique_ptr<tb_scene, decltype(&tb_scene_destroy)> scene(raw, tb_scene_destroy);
    std::vector<double> heights;
    auto record = [](size_t, double, const tb_scene *s, void *ctx) {
        static_cast<std::vector<double> *>(ctx)->push_back(tb_scene_states_const(s)[2]);
        return 0;
    };
    if (tb_scene_run(scene.get(), &run, record, &heights, nullptr, &error) != TB_STATUS_OK) {
        std::fprintf(stderr, "%s\n", error.message);
        return 1;
    }
    const double expected = 10.0 - 0.5 * 9.81;
    const bool ok = heights.size() == 11 && std::fabs(heights.back() - expected) < 1e-12;
    std::printf("C++: %zu frames, ball at z = %.12f (%s)\n", heights.size(), heights.back(),
                ok ? "ok" : "WRONG");
    return ok ? 0 : 1;
}
