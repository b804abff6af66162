//! One file per command.

mod analyze;
mod analyze_inputs;
mod analyze_tool;
mod axis;
mod convert;
mod diff;
mod dynamometer;
mod emg;
mod flatten;
mod forward;
mod id;
mod ik;
mod info;
mod plot;
mod reaction;
mod run;
mod scale;
mod scale_functional;
mod set;
mod cmc;
mod rra;
mod simulate;
mod so;
mod trials;

use super::{AnalyzeArgs, Command, Failure, Outcome};

pub fn run(command: Command) -> Result<Outcome, Failure> {
    match command {
        Command::Analyze { model, motion, output, setup: Some(setup), .. } => analyze_tool::run(&model, &motion, &setup, &output),
        Command::Analyze { model, motion, output, skip_unknown_columns, activation, activations, setup: None } => {
            let fibers = match (activation, activations) {
                (Some(a), _) => Some(analyze::FiberInput::Uniform(a)),
                (None, Some(file)) => Some(analyze::FiberInput::File(file)),
                (None, None) => None,
            };
            analyze::run(&model, &motion, &output, skip_unknown_columns, fibers)
        }
        Command::Info { model, json } => info::run(&model, json),
        Command::Run { setup, dry_run } => run::run(&setup, dry_run),
        Command::Axis { trial, femur, tibia, method, poses, epicondyles, model, swap, reference_angle, output, json } => {
            let swap = swap.zip(output).map(|(joint, output)| axis::Swap { joint, output, reference_angle: reference_angle.map(f64::to_radians) });
            let request = axis::Request { femur, tibia, method, poses, epicondyles, model, swap, json };
            axis::run(&trial, &request)
        }
        Command::Set { input, output, assignments } => set::run(&input, &output, &assignments),
        Command::Convert { input, output } => convert::run(&input, &output),
        Command::Diff { a, b, json, rtol } => diff::run(&a, &b, json, rtol),
        Command::Flatten { document } => flatten::run(&document),
        Command::Plot { tables, columns, x, title, y_label, output } => plot::run(&tables, &plot::Request { columns, x, title, y_label }, &output),
        Command::Id { model, coordinates, external_loads, setup, time, lowpass, rates, body_force_joints, body_forces, output } => {
            let request = id::Request { external_loads, setup, time: time.map(|t| [t[0], t[1]]), lowpass, rates, body_force_joints, body_forces, output };
            id::run(&model, &coordinates, &request)
        }
        Command::Dynamometer {
            model,
            coordinates,
            load_cell,
            crank,
            knee,
            dynamometer_moment,
            dynamometer_sign,
            time,
            lowpass,
            perturb_axis_angle,
            perturb_axis_offset,
            perturb_mass,
            perturb_mass_center,
            json,
            report,
            output,
        } => {
            let perturbations = crate::analysis::Perturbations { axis_angle: perturb_axis_angle.to_radians(), axis_offset: perturb_axis_offset, mass: perturb_mass, mass_center: perturb_mass_center };
            let time = time.map(|t| [t[0], t[1]]);
            let request = dynamometer::Request { load_cell, crank, knee, dynamometer_moment, dynamometer_sign: if dynamometer_sign == "-1" { -1.0 } else { 1.0 }, time, lowpass, perturbations, json, report, output };
            dynamometer::run(&model, &coordinates, &request)
        }
        Command::Trials { model, session, plateau_fraction, max_crank_motion, output } => trials::run(&model, &session, &trials::Request { plateau_fraction, max_crank_motion, output }),
        Command::Emg { predicted, emg, pair, max_lag, json } => emg::run(&predicted, &emg, &pair, max_lag, json),
        Command::Simulate { model, setup, output } => simulate::run(&model, &setup, &output),
        Command::Rra { model, setup, output } => rra::run(&model, &setup, &output),
        Command::Cmc { model, setup, output } => cmc::run(&model, &setup, &output),
        Command::Forward { model, coordinates, excitations, activations, inverse_dynamics, time, lowpass, accuracy, name, output } => {
            let request = forward::Request { excitations, activations, inverse_dynamics, time: time.map(|t| [t[0], t[1]]), lowpass, accuracy, name, output };
            forward::run(&model, &coordinates, &request)
        }
        Command::So { model, coordinates, setup, analyze, activation_exponent, compare, pia, time_constant_scale, compliant_tendons, moment_weight } => {
            let AnalyzeArgs { external_loads, actuators, time, lowpass, step_interval, states, name, output } = analyze;
            let (time, pia) = (time.map(|t| [t[0], t[1]]), pia.map(Into::into));
            let request = so::Request { setup, external_loads, actuators, time, lowpass, step_interval, states, activation_exponent, compare, pia, time_constant_scale, compliant_tendons, moment_weight, name, output };
            so::run(&model, &coordinates, &request)
        }
        Command::Reaction { model, coordinates, forces, setup, analyze, joints, on, frames } => {
            let AnalyzeArgs { external_loads, actuators, time, lowpass, step_interval, states, name, output } = analyze;
            let time = time.map(|t| [t[0], t[1]]);
            let request = reaction::Request { forces, setup, external_loads, actuators, time, lowpass, step_interval, states, joints, on, frames, name, output };
            reaction::run(&model, &coordinates, &request)
        }
        Command::Ik { model, trial, setup, time, weights, kalman, kalman_rates, output, errors, marker_locations } => {
            let request = ik::Request { setup: setup.as_deref(), time: time.map(|t| [t[0], t[1]]), weights: &weights, kalman };
            ik::run(&model, &trial, &request, &ik::Outputs { motion: output, errors, kalman_rates, marker_locations })
        }
        Command::Scale {
            model,
            trials,
            method,
            sets,
            muscles,
            rest_tolerance,
            rest_constraint,
            no_rest_curve,
            prior_sd,
            no_prior,
            map,
            group_ratios,
            noise_sd,
            sigma_points,
            force,
            report,
            cause_model,
            figures,
            setup,
            linear,
            output,
            scaled_only,
            scale_set,
            static_pose,
            marker_set,
            json,
        } => match trials.as_deref().filter(|folder| !linear && setup.is_none() && scale_functional::is_dynamometry(folder)) {
            Some(folder) => {
                let options = scale_functional::Options { method, rest_tolerance, rest_constraint, rest_curve: !no_rest_curve, prior_sd, no_prior, map, group_ratios, noise_sd, sigma_points };
                let settings = options.settings();
                let request = scale_functional::Request { sets, muscles, settings, force, report, cause_model, figures, json };
                scale_functional::run(&model, folder, &output, &request)
            }
            None => {
                let outputs = scale::Outputs { model: output, scaled_only, scale_set, static_pose, marker_set };
                scale::run(&model, trials.as_deref(), setup.as_deref(), linear, &outputs, json)
            }
        },
    }
}
