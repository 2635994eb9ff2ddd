/* Prints, as JSON, the size and field offsets of the structs the Python bindings declare with
 * ctypes, compiled against the real headers: tests/test_layout.py compares the two, so the
 * bindings cannot drift from the C library silently. The wheel ships this output
 * (tumble/layout.json) with the headers' version, and the package checks both at import. */
#include "tumble/joints.h"
#include "tumble/tumble.h"

#include <stddef.h>
#include <stdio.h>

#define FIELD(type, field) printf("\"%s\": %zu, ", #field, offsetof(type, field))

int main(void)
{
    printf("{\"version\": \"%s\",\n", TB_VERSION_STRING);
    printf("\"tb_contact_event\": {\"size\": %zu, ", sizeof(tb_contact_event));
    FIELD(tb_contact_event, kind);
    FIELD(tb_contact_event, t);
    FIELD(tb_contact_event, body_a);
    FIELD(tb_contact_event, body_b);
    FIELD(tb_contact_event, point);
    FIELD(tb_contact_event, normal);
    FIELD(tb_contact_event, speed);
    FIELD(tb_contact_event, impulse);
    FIELD(tb_contact_event, effect);
    printf("\"_\": 0},\n");
    printf("\"tb_contact_events_def\": {\"size\": %zu, ", sizeof(tb_contact_events_def));
    FIELD(tb_contact_events_def, fn);
    FIELD(tb_contact_events_def, ctx);
    FIELD(tb_contact_events_def, hit_threshold);
    FIELD(tb_contact_events_def, pair_capacity);
    FIELD(tb_contact_events_def, internal_cookie);
    printf("\"_\": 0},\n");
    printf("\"tb_impact\": {\"size\": %zu, ", sizeof(tb_impact));
    FIELD(tb_impact, t);
    FIELD(tb_impact, body_a);
    FIELD(tb_impact, body_b);
    FIELD(tb_impact, effect);
    FIELD(tb_impact, speed);
    FIELD(tb_impact, duration);
    FIELD(tb_impact, steps);
    printf("\"_\": 0},\n");
    printf("\"tb_unresolved_impacts\": {\"size\": %zu, ", sizeof(tb_unresolved_impacts));
    FIELD(tb_unresolved_impacts, watched);
    FIELD(tb_unresolved_impacts, dt);
    FIELD(tb_unresolved_impacts, resolution);
    FIELD(tb_unresolved_impacts, count);
    FIELD(tb_unresolved_impacts, first);
    FIELD(tb_unresolved_impacts, fastest);
    printf("\"_\": 0},\n");
    printf("\"tb_joint_def\": {\"size\": %zu, ", sizeof(tb_joint_def));
    FIELD(tb_joint_def, type);
    FIELD(tb_joint_def, body_a);
    FIELD(tb_joint_def, body_b);
    FIELD(tb_joint_def, anchor);
    FIELD(tb_joint_def, axis);
    FIELD(tb_joint_def, has_limits);
    FIELD(tb_joint_def, limits);
    FIELD(tb_joint_def, restitution);
    FIELD(tb_joint_def, motor);
    FIELD(tb_joint_def, motor_speed);
    FIELD(tb_joint_def, motor_target);
    FIELD(tb_joint_def, motor_max_force);
    FIELD(tb_joint_def, break_force);
    FIELD(tb_joint_def, break_torque);
    FIELD(tb_joint_def, soft_frequency);
    FIELD(tb_joint_def, soft_damping_ratio);
    FIELD(tb_joint_def, internal_cookie);
    printf("\"_\": 0},\n");
    printf("\"tb_error\": {\"size\": %zu, ", sizeof(tb_error));
    FIELD(tb_error, status);
    FIELD(tb_error, message);
    printf("\"_\": 0},\n");

    printf("\"tb_integrator_def\": {\"size\": %zu, ", sizeof(tb_integrator_def));
    FIELD(tb_integrator_def, method);
    FIELD(tb_integrator_def, dt);
    FIELD(tb_integrator_def, rtol);
    FIELD(tb_integrator_def, atol);
    FIELD(tb_integrator_def, atol_vector);
    FIELD(tb_integrator_def, max_steps);
    FIELD(tb_integrator_def, initial_step);
    FIELD(tb_integrator_def, max_step);
    FIELD(tb_integrator_def, max_order);
    FIELD(tb_integrator_def, linear_solver);
    FIELD(tb_integrator_def, preconditioner_half_bandwidth);
    FIELD(tb_integrator_def, threads);
    FIELD(tb_integrator_def, internal_cookie);
    printf("\"_\": 0},\n");

    printf("\"tb_run_def\": {\"size\": %zu, ", sizeof(tb_run_def));
    FIELD(tb_run_def, integrator);
    FIELD(tb_run_def, fps);
    FIELD(tb_run_def, duration);
    FIELD(tb_run_def, internal_cookie);
    printf("\"_\": 0},\n");

    printf("\"tb_mass_properties\": {\"size\": %zu, ", sizeof(tb_mass_properties));
    FIELD(tb_mass_properties, mass);
    FIELD(tb_mass_properties, center);
    FIELD(tb_mass_properties, moments);
    FIELD(tb_mass_properties, rotation);
    printf("\"_\": 0},\n");

    printf("\"tb_integrator_stats\": {\"size\": %zu, ", sizeof(tb_integrator_stats));
    FIELD(tb_integrator_stats, steps);
    FIELD(tb_integrator_stats, derivative_evals);
    FIELD(tb_integrator_stats, jacobian_derivative_evals);
    FIELD(tb_integrator_stats, failed_steps);
    FIELD(tb_integrator_stats, error_test_failures);
    FIELD(tb_integrator_stats, nonlinear_failures);
    FIELD(tb_integrator_stats, linear_iterations);
    FIELD(tb_integrator_stats, last_step);
    FIELD(tb_integrator_stats, current_step);
    FIELD(tb_integrator_stats, last_order);
    FIELD(tb_integrator_stats, current_order);
    FIELD(tb_integrator_stats, reinitializations);
    FIELD(tb_integrator_stats, nonlinear_iterations);
    FIELD(tb_integrator_stats, jacobian_evals);
    FIELD(tb_integrator_stats, rest_time);
    printf("\"_\": 0},\n");

    printf("\"tb_accuracy_setting\": {\"size\": %zu, ", sizeof(tb_accuracy_setting));
    FIELD(tb_accuracy_setting, method);
    FIELD(tb_accuracy_setting, setting);
    printf("\"_\": 0},\n");

    printf("\"tb_accuracy_def\": {\"size\": %zu, ", sizeof(tb_accuracy_def));
    FIELD(tb_accuracy_def, settings);
    FIELD(tb_accuracy_def, setting_count);
    FIELD(tb_accuracy_def, reference_rtol);
    FIELD(tb_accuracy_def, check_rtol);
    FIELD(tb_accuracy_def, max_steps);
    FIELD(tb_accuracy_def, reference);
    FIELD(tb_accuracy_def, reference_step_fraction);
    FIELD(tb_accuracy_def, horizon_tolerance);
    FIELD(tb_accuracy_def, progress);
    FIELD(tb_accuracy_def, progress_ctx);
    FIELD(tb_accuracy_def, internal_cookie);
    printf("\"_\": 0},\n");

    printf("\"tb_accuracy_result\": {\"size\": %zu, ", sizeof(tb_accuracy_result));
    FIELD(tb_accuracy_result, method);
    FIELD(tb_accuracy_result, setting);
    FIELD(tb_accuracy_result, status);
    FIELD(tb_accuracy_result, detail);
    FIELD(tb_accuracy_result, error);
    FIELD(tb_accuracy_result, position_error);
    FIELD(tb_accuracy_result, angle_error);
    FIELD(tb_accuracy_result, cpu_seconds);
    FIELD(tb_accuracy_result, steps);
    FIELD(tb_accuracy_result, derivative_evals);
    FIELD(tb_accuracy_result, energy_error);
    printf("\"_\": 0},\n");

    printf("\"tb_accuracy_reference\": {\"size\": %zu, ", sizeof(tb_accuracy_reference));
    FIELD(tb_accuracy_reference, error);
    FIELD(tb_accuracy_reference, position_error);
    FIELD(tb_accuracy_reference, angle_error);
    FIELD(tb_accuracy_reference, method);
    FIELD(tb_accuracy_reference, setting);
    FIELD(tb_accuracy_reference, check_setting);
    FIELD(tb_accuracy_reference, horizon);
    FIELD(tb_accuracy_reference, horizon_frames);
    FIELD(tb_accuracy_reference, frames);
    FIELD(tb_accuracy_reference, energy_error);
    FIELD(tb_accuracy_reference, cvode_detail);
    printf("\"_\": 0},\n");

    printf("\"tb_body_state\": {\"size\": %zu, ", sizeof(tb_body_state));
    FIELD(tb_body_state, x);
    FIELD(tb_body_state, q);
    FIELD(tb_body_state, P);
    FIELD(tb_body_state, L);
    printf("\"_\": 0},\n");

    printf("\"tb_writer_def\": {\"size\": %zu, ", sizeof(tb_writer_def));
    FIELD(tb_writer_def, format);
    FIELD(tb_writer_def, rotation_keys);
    FIELD(tb_writer_def, scene_file);
    FIELD(tb_writer_def, scene_text);
    FIELD(tb_writer_def, base_directory);
    FIELD(tb_writer_def, frame_count);
    FIELD(tb_writer_def, fps);
    FIELD(tb_writer_def, sample_tolerance);
    FIELD(tb_writer_def, internal_cookie);
    printf("\"_\": 0}}\n");
    return 0;
}
