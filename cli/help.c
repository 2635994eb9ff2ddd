/* The help texts: the program's, and each command's own (tumble run --help). */
#include "options.h"

static const char program_help[] =
    "usage: tumble run SCENE.json [options]       simulate and write frames as CSV\n"
    "       tumble check SCENE.json [options]     validate a scene and its run without running\n"
    "       tumble accuracy SCENE.json [options]  error against cost of every integrator\n"
    "       tumble COMMAND --help                 the command's options\n"
    "       tumble --help | --version\n"
    "\n"
    "Options may come before or after the scene, as --name VALUE or --name=VALUE; an option\n"
    "that does not apply to the command, or is given twice, is refused. Exit codes: 0 success,\n"
    "1 the simulation or writing its output failed, 2 bad input (usage, scene file, settings).\n"
    "The scene format is described in docs/scene-format.md (share/tumble/docs when installed).\n";

static const char run_help[] =
    "usage: tumble run SCENE.json [options]\n"
    "Simulates the scene and writes its frames (each option overrides the scene file):\n"
    "  --integrator M    euler, midpoint, rk4, rosenbrock (linearly implicit) (fixed step) or\n"
    "                    cvode-adams, cvode-bdf, ark-imex (adaptive)\n"
    "  --dt H            step size in seconds, for fixed-step methods\n"
    "  --rtol R          relative tolerance, for adaptive methods (e.g. 1e-6)\n"
    "  --atol A          absolute tolerance, for adaptive methods (0: derived from the bodies)\n"
    "  --max-steps N     steps allowed from one frame to the next, every method (default 100000)\n"
    "  --fps F           frames per second written\n"
    "  --duration T      seconds simulated\n"
    "  -o, --out FILE    where the frames go (default: standard output; never the scene file)\n"
    "  --format F        csv, npz (NumPy arrays), glb or gltf (animated glTF 2.0 with the\n"
    "                    shapes, for Blender and browsers) or usda (USD text, for usdview,\n"
    "                    Houdini, Omniverse); default: --out's extension, else csv\n"
    "  --rotation K      glTF rotation keys: cubic (default: a spline following the spin) or\n"
    "                    linear\n"
    "  --events FILE     contact events (begin, hit, end of touching pairs) to FILE.csv or\n"
    "                    FILE.json: t,kind,body_a,body_b,x,y,z,nx,ny,nz,speed,impulse\n"
    "  --hit-speed V     with --events: leave out hits closing slower than V m/s (default 0)\n"
    "  --joints FILE     each joint's reaction on its first body per frame, as CSV:\n"
    "                    t,joint,fx,fy,fz,tx,ty,tz,broken (N and N m, world frame; the\n"
    "                    torque about the anchor; broken 0 or 1)\n"
    "  --project-joints  project the start onto the joints first (tb_scene_project_joints)\n"
    "  -h, --help        this help\n"
    "\n"
    "The CSV (RFC 4180: a body name with a comma, quote or line break is quoted) has one row\n"
    "per body per frame:\n"
    "  t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"
    "all in the world frame and SI units: the position and unit quaternion of the body's\n"
    "shape frame (the frame its shape is described in, so a model can be placed with them),\n"
    "that frame origin's velocity, and the angular velocity, with 17 significant digits (they\n"
    "read back exactly); npz holds the same as arrays. docs/export.md describes every format\n"
    "(tumble's world is z up; glTF files turn it to glTF's y up). A summary goes to standard "
    "error:\n"
    "the integrator's work and the drift of what the scene's effects conserve (energy, linear\n"
    "momentum, angular momentum about the centre of mass of all bodies).\n"
    "Exit codes: 0 success, 1 the simulation or a write failed, 2 bad input.\n";

static const char check_help[] =
    "usage: tumble check SCENE.json [options]\n"
    "Loads the scene and checks the run it asks for (with the overrides given) as tumble run\n"
    "would, without running it: a step beyond the stability limit, too many frames, a setting\n"
    "that does not apply to the method are refused here as they would be there.\n"
    "  --integrator M, --dt H, --rtol R, --atol A, --max-steps N, --fps F, --duration T\n"
    "                    as for tumble run\n"
    "  --project-joints  project the start onto the joints first (positions, then velocities,\n"
    "                    to 1e-12: tb_scene_project_joints), then check it\n"
    "  -h, --help        this help\n"
    "It prints, on standard error, the step each fixed-step method would take with dt 0 (the\n"
    "scene's default step), the steps per simulated second, and the stability limit with what\n"
    "sets it, as the library gives them.\n"
    "On a scene with contact or ground planes it also prints what collides with what: each\n"
    "contact effect's bodies and material, the ground planes and the bodies they touch, the\n"
    "shapes, the pairs touching at the start (with their depth), and warnings (two contact\n"
    "effects on one pair, a deep overlap at the start, a named body without a shape).\n"
    "On a scene with joints it prints each joint (type, bodies) and how far the start is off\n"
    "it, and refuses a start off a joint by more than 1e-6 (m or rad, m/s or rad/s) unless\n"
    "--project-joints is given.\n"
    "Exit codes: 0 the scene would run, 1 writing the report failed, 2 it would be refused.\n";

static const char accuracy_help[] =
    "usage: tumble accuracy SCENE.json [options]\n"
    "Runs the scene with every integrator over a sweep of its setting against a tight\n"
    "reference (cvode-bdf, rtol 1e-11), prints position and orientation errors, CPU time,\n"
    "derivative evaluations and the final energy difference, and names the cheapest setting\n"
    "whose error is at most E metres.\n"
    "  --target-error E  the error budget in metres of visible displacement (default 1e-3)\n"
    "  --chart FILE.svg  also draw error against CPU time\n"
    "  --fps F           frames compared per second (default: the scene's)\n"
    "  --duration T      seconds simulated (default: the scene's)\n"
    "  -h, --help        this help\n"
    "Every integrator runs, so --integrator, --dt, --rtol and --atol do not apply; the table\n"
    "goes to standard output. On a stiff scene the explicit fixed-step methods run at 1, 2 and\n"
    "4 times the rate of their default step (rosenbrock, implicit, at 240 and 1000 steps/s).\n"
    "When the cvode-bdf reference fails (stiff contact), the\n"
    "reference is rk4 at 1/8 of the default step, checked at 1/4. Frames are compared up to\n"
    "the horizon, where the two references still agree to E/10 (chaos: past it no two runs\n"
    "agree); the energy difference at the last frame is a statistic that holds past it.\n"
    "On contact scenes an adaptive setting that needs more than 4 times the rk4 reference's\n"
    "steps in a frame, or (rk4 reference) 1.5 times the reference run's CPU, is listed as\n"
    "failed. Progress goes to standard error: a line per setting done, and one every 5 s\n"
    "within a run.\n"
    "Exit codes: 0 success, 1 the reference run or a write failed, 2 bad input.\n";

const char *cli_help(cli_command command)
{
    switch (command) {
    case CLI_RUN:
        return run_help;
    case CLI_CHECK:
        return check_help;
    case CLI_ACCURACY:
        return accuracy_help;
    }
    return program_help;
}
