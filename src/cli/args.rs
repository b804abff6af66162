//! Arguments of every command, as plain structs (clap derive).
//!
//! The doc comments are the commands' `--help` text, where `<coordinate>` is a placeholder as in
//! any usage line, not an HTML tag.
#![allow(rustdoc::invalid_html_tags)]

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// Turn generic OpenSim models into subject-specific ones.
///
/// Exit codes: 0 success, 1 differences found (diff), 2 error.
#[derive(Debug, Parser)]
#[command(name = "osim-tune", version, about)]
pub struct Arguments {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Summarise a model: bodies, joints by type, coordinates with ranges and units, muscles by
    /// class, markers, constraints and wrap objects.
    Info {
        /// The model (.osim, OpenSim 4.x or 3.x).
        model: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Edit property values by component path and write the result to a new file.
    ///
    /// Each ASSIGNMENT is PATH=VALUE, e.g. /forceset/vas_lat_r/tendon_slack_length=0.17 or
    /// /markerset/R.ASIS/location="0.01 0 0.13". Paths are OpenSim component paths; a property
    /// is addressed by its XML name. Only the edited values change in the output; with no
    /// assignment the output is a byte-identical copy. Numbers must stay numbers (with the same
    /// count), booleans true/false. Any error writes nothing.
    Set {
        /// The document to edit (.osim model or OpenSim setup .xml); never overwritten.
        input: PathBuf,
        /// Where to write the edited document.
        #[arg(short, long)]
        output: PathBuf,
        /// PATH=VALUE edits.
        assignments: Vec<String>,
    },
    /// Convert a 2.x/3.x model into OpenSim 4's format as OpenSim 4 converts it when it opens
    /// one (joints out of bodies with offset frames, sockets, attached geometry; values it
    /// passes through a stream at six significant digits). OpenSim 4 reads the result as it reads
    /// the original; a 4.x model is copied unchanged.
    Convert {
        /// The model to convert; never overwritten.
        input: PathBuf,
        /// Where to write the 4.x model.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Semantic diff of two OpenSim documents for review: added and removed components, changed
    /// properties with old → new and the relative change of numbers. Formatting, comments and
    /// number spelling (0.1 vs 1.0e-01) are ignored. Exit 0 same, 1 different, 2 error.
    ///
    /// As a git difftool: git difftool -x 'osim-tune diff' -- '*.osim'
    Diff {
        a: PathBuf,
        b: PathBuf,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
        /// Treat numbers as equal when |a − b| ≤ RTOL·max(|a|, |b|).
        #[arg(long, default_value_t = 0.0)]
        rtol: f64,
    },
    /// OpenSim's Scale step: marker set, scale factors from marker-pair measurements and manual
    /// factors, the model scaled (frames, joints, markers, path points, masses, inertias,
    /// L_opt and L_ts by path length), then markers placed on the static trial.
    ///
    /// Either --setup SETUP.xml (an OpenSim ScaleTool setup, 2.x–4.x; its model_file is
    /// replaced by MODEL and its output file names are ignored — use the options below), or a
    /// TRIALS folder with --linear (see README: subject.json with the mass and static trial,
    /// and the built-in gait2392 measurement set unless the folder names a setup).
    ///
    /// Functional scaling: a TRIALS folder of isometric dynamometry (subject.json with
    /// "trial_files", one .mot per set and direction; see README) fits L_opt and L_ts of the
    /// estimated knee muscles to the measured knee moments (thesis ch. 6) and writes the model
    /// with only those values changed, plus a report. Exit 1 (and no model unless --force)
    /// when the fit does not converge.
    Scale {
        /// The generic model (.osim, OpenSim 4).
        model: PathBuf,
        /// Trials folder: dynamometry trials (functional scaling) or, with --linear, a static trial.
        trials: Option<PathBuf>,
        /// Functional scaling estimator.
        #[arg(long, value_enum, default_value_t = ScaleMethodArgument::Functional)]
        method: ScaleMethodArgument,
        /// Functional: trial sets to use, comma-separated (e.g. set5,set10); default all.
        #[arg(long, value_delimiter = ',')]
        sets: Option<Vec<String>>,
        /// Functional: the muscles whose L_opt and L_ts are estimated, comma-separated; default the
        /// subject file's estimated_muscles.
        #[arg(long, value_delimiter = ',')]
        muscles: Option<Vec<String>>,
        /// Functional: accepted rest fiber length deviation in Phase I, relative (thesis Δ; default 0.1).
        #[arg(long)]
        rest_tolerance: Option<f64>,
        /// Functional: also constrain the rest fiber length in Phase II to ± this fraction.
        #[arg(long)]
        rest_constraint: Option<f64>,
        /// Functional: stop after Phase II (the thesis' method) instead of then fitting with every rest fiber length held at its reference.
        #[arg(long)]
        no_rest_curve: bool,
        /// Functional: τ of the rest-curve fit's Gaussian prior around the model's L_opt (relative sd; default 0.1), weighed against the moment noise σ.
        #[arg(long, conflicts_with_all = ["no_prior", "no_rest_curve"])]
        prior_sd: Option<f64>,
        /// Functional: plain least squares in the rest-curve fit (no prior around the model's values).
        #[arg(long)]
        no_prior: bool,
        /// Functional: with the prior, report its maximum a-posteriori fit instead of the posterior mean (sampled on the search's tables).
        #[arg(long, conflicts_with_all = ["no_prior", "no_rest_curve"])]
        map: bool,
        /// Functional: tie the vasti's and gastrocnemii's L_opt within 0.9–1.1 of each other (eq. 6.23–6.24).
        #[arg(long)]
        group_ratios: bool,
        /// Functional: moment noise σ in N·m, weighed against the rest-curve prior and used for the uncertainty (default: subject.json's, else estimated from the moments by their marginal likelihood under the prior).
        #[arg(long)]
        noise_sd: Option<f64>,
        /// Functional: propagate the noise through the fit at the 2n²+1 sigma points (slow: one refit per point; Garner & Pandy too).
        #[arg(long)]
        sigma_points: bool,
        /// Functional: write the model even when the fit did not converge.
        #[arg(long)]
        force: bool,
        /// Functional: also write the report as JSON to this file.
        #[arg(long)]
        report: Option<PathBuf>,
        /// Functional: also write the model extended by the single cause the report's verdict names (a muscle's or a group's parameter set to its fitted value, or the knee's two offset frames moved with its axis; nothing else changed); when the verdict names none, or a cause in the trials or the measured moments (an angle offset, an activation level, a moment offset), it says so and writes nothing.
        #[arg(long)]
        cause_model: Option<PathBuf>,
        /// Functional: also draw figures into this folder (SVG, created if needed): per trial set the knee moment against the knee angle — measured, initial and fitted model — and per estimated muscle its Phase I feasible set with the regression line, the initial and the fitted L_opt and L_ts.
        #[arg(long)]
        figures: Option<PathBuf>,
        /// ScaleTool setup file.
        #[arg(long)]
        setup: Option<PathBuf>,
        /// Linear (ScaleTool) scaling of a trials folder.
        #[arg(long)]
        linear: bool,
        /// The subject-specific model to write.
        #[arg(short, long)]
        output: PathBuf,
        /// Also write the model after scaling, before marker placement.
        #[arg(long)]
        scaled_only: Option<PathBuf>,
        /// Also write the scale factors as an OpenSim ScaleSet file.
        #[arg(long)]
        scale_set: Option<PathBuf>,
        /// Also write the static pose found by marker placement (.mot, degrees).
        #[arg(long)]
        static_pose: Option<PathBuf>,
        /// Also write the model's markers (placed, when markers are placed) as an OpenSim
        /// MarkerSet file, as the MarkerPlacer's output_marker_file.
        #[arg(long)]
        marker_set: Option<PathBuf>,
        /// Print the summary as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Muscle-tendon lengths, moment arms and marker locations along a motion, like OpenSim's
    /// MuscleAnalysis: writes DIR/Length.sto (one column per muscle, m),
    /// DIR/MomentArm_<coordinate>.sto for every coordinate some muscle spans (m, or m/m) and
    /// DIR/MarkerLocations.sto (<marker>_tx/_ty/_tz in ground, m).
    ///
    /// Motion columns are coordinate names (or /…/<coordinate>/value paths), in degrees or
    /// radians per the header; coordinates the motion lacks stay at their default; a column
    /// that is no coordinate of the model is an error unless --skip-unknown-columns (speed
    /// columns are always skipped). Values are used as given, without clamping to ranges.
    Analyze {
        /// The model (.osim).
        model: PathBuf,
        /// Coordinate trajectories (.mot or .sto), e.g. an inverse kinematics result.
        #[arg(long)]
        motion: PathBuf,
        /// Output folder (created if needed); existing files of the same names are replaced.
        #[arg(short, long)]
        output: PathBuf,
        /// Skip motion columns that are no coordinate of the model (e.g. the marker and force
        /// columns of a legacy IK .mot) instead of failing.
        #[arg(long)]
        skip_unknown_columns: bool,
        /// Also solve each muscle's static fiber–tendon equilibrium at this activation (0…1, all
        /// muscles) and write FiberLength, NormFiberLength, PennationAngle, TendonLength,
        /// TendonForce, ActiveFiberForce, PassiveFiberForce and Moment_<coordinate> tables.
        #[arg(long, conflicts_with = "activations")]
        activation: Option<f64>,
        /// Like --activation, with per-muscle activations from a .sto (a column per muscle,
        /// e.g. a static optimisation activation.sto), interpolated linearly in time.
        #[arg(long)]
        activations: Option<PathBuf>,
        /// An OpenSim AnalyzeTool setup: its MuscleAnalysis, Kinematics, BodyKinematics,
        /// PointKinematics, ForceReporter, Actuation, StatesReporter, ProbeReporter (muscle
        /// metabolics probes), InducedAccelerations (the
        /// external forces replaced by its rolling or point contacts) and a JointReaction without
        /// a forces file run as OpenSim's AnalyzeTool runs them — its time range, coordinate cutoff
        /// (filtered and splined states, coordinates the motion lacks held at 0; or, when the
        /// setup names a states_file, --motion is that states file), the muscles at their
        /// default or equilibrium states, force-set files, external loads, the model's and the setup's
        /// ControlSetControllers and PrescribedControllers,
        /// each analysis's step interval and lists — writing DIR/<name>_<analysis>_<table>.sto
        /// (Length, FiberLength, …, MomentArm_<coordinate>, Moment_<coordinate>, q, u, dudt,
        /// pos_global, vel_global, acc_global, <point>_pos, forces, force, speed, power, states,
        /// ReactionLoads); columns that are no coordinate are skipped.
        #[arg(long, conflicts_with_all = ["activation", "activations", "skip_unknown_columns"])]
        setup: Option<PathBuf>,
    },
    /// Inverse kinematics like OpenSim 4.6's InverseKinematicsTool: per frame, the pose that
    /// minimises the weighted squared distances between model markers and the trial's markers
    /// (locked coordinates held, clamped ones within their range, couplers exact), each frame
    /// starting from the previous one. Writes the coordinates as OpenSim's IK .mot (degrees)
    /// and, with --errors, OpenSim's marker-error table. Markers missing in a frame are dropped
    /// for that frame. Exit 0 success, 1 some frame did not converge, 2 error.
    Ik {
        /// The model (.osim).
        model: PathBuf,
        /// Marker trajectories (.trc, any length unit).
        trial: PathBuf,
        /// An OpenSim InverseKinematicsTool setup: its marker and coordinate tasks, weights and
        /// time range are used (its model and marker file names are not; --time and --weights
        /// override it).
        #[arg(long)]
        setup: Option<PathBuf>,
        /// Time range in seconds (clipped to the trial; each end goes to the nearest frame).
        #[arg(long, num_args = 2, value_names = ["START", "END"], allow_negative_numbers = true)]
        time: Option<Vec<f64>>,
        /// Marker weights NAME=W (default 1 for every model marker in the trial), comma
        /// separated, e.g. R.ASIS=10,L.ASIS=10; W = 0 only reports the marker.
        #[arg(long, value_delimiter = ',')]
        weights: Vec<String>,
        /// Kalman-smooth the kinematics over the whole trial at about this cutoff (Hz), as the
        /// thesis computes joint kinematics (De Groote et al. 2008): the markers through the
        /// model with their weights, each coordinate's 4th derivative constant up to noise; links
        /// between bodies held (the smoothed poses, speeds and accelerations projected onto
        /// them). Not OpenSim's IK.
        #[arg(long)]
        kalman: Option<f64>,
        /// With --kalman: also write the smoother's speeds and accelerations of every coordinate
        /// (`<coordinate>_speed`, `_acceleration`; rad/s, rad/s² or m/s, m/s²) to this file (.sto).
        #[arg(long)]
        kalman_rates: Option<PathBuf>,
        /// Output coordinates (.mot, OpenSim's IK layout, rotations in degrees).
        #[arg(short, long)]
        output: PathBuf,
        /// Also write total squared error, RMS and max marker error per frame (.sto).
        #[arg(long)]
        errors: Option<PathBuf>,
        /// Also write the tracked markers' locations in ground per frame (`<marker>_tx`, `_ty`,
        /// `_tz`, m; .sto), as OpenSim's report_marker_locations.
        #[arg(long)]
        marker_locations: Option<PathBuf>,
    },
    /// Run an OpenSim tool setup as `opensim-cmd run-tool` does: a ScaleTool,
    /// InverseKinematicsTool, InverseDynamicsTool, AnalyzeTool (MuscleAnalysis, Kinematics,
    /// BodyKinematics, PointKinematics, ForceReporter, Actuation, StatesReporter,
    /// ProbeReporter, InducedAccelerations, StaticOptimization, JointReaction), ForwardTool (`simulate`), RRATool (`rra`) or CMCTool (`cmc`) setup's model, input
    /// and output files (relative names from the setup's
    /// folder; outputs under OpenSim's names, e.g. <results_directory>/<name>_ik_marker_errors.sto)
    /// given to the osim-tune command that does the tool's work, printed before it runs. Exit as
    /// that command: 0 success, 1 a frame did not converge or a simulation or tracking failed, 2 error.
    Run {
        /// The setup (.xml), OpenSim 2.x–4.x.
        setup: PathBuf,
        /// Only print the commands.
        #[arg(long)]
        dry_run: bool,
    },
    /// Inverse dynamics like OpenSim 4.6's InverseDynamicsTool: the coordinates (degrees per the
    /// header) are padded and low-pass filtered when a cutoff is given (OpenSim's 3rd-order
    /// Butterworth run forward and backward, resampled at the smallest step first), q, q̇ and q̈
    /// come from degree-5 GCV splines, and the generalized forces that produce them with gravity
    /// and the external loads are written in Simbody's coordinate order (`<coordinate>_moment`,
    /// N·m, or `_force`, N). Model forces (muscles, springs, …) are not applied: a setup's
    /// forces_to_exclude must exclude them. Exit 0 success, 2 error.
    Id {
        /// The model (.osim).
        model: PathBuf,
        /// Coordinate trajectories (.mot or .sto), e.g. an inverse kinematics result.
        coordinates: PathBuf,
        /// An OpenSim ExternalLoads file (.xml) with its datafile (force-plate forces, points,
        /// torques); overrides the setup's.
        #[arg(long)]
        external_loads: Option<PathBuf>,
        /// An OpenSim InverseDynamicsTool setup: its time range, coordinate cutoff and external
        /// loads are used (its model and coordinates file names are not; --time, --lowpass and
        /// --external-loads override it).
        #[arg(long)]
        setup: Option<PathBuf>,
        /// Time range in seconds (clipped to the coordinates; each end goes to the frame at or
        /// before it).
        #[arg(long, num_args = 2, value_names = ["START", "END"], allow_negative_numbers = true)]
        time: Option<Vec<f64>>,
        /// Low-pass cutoff frequency for the coordinates, Hz (default: the setup's, else none).
        #[arg(long, conflicts_with = "rates")]
        lowpass: Option<f64>,
        /// The coordinates' speeds and accelerations per frame (`<coordinate>_speed`,
        /// `_acceleration`, e.g. `ik --kalman HZ --kalman-rates`): used as they are, the
        /// coordinates neither filtered nor splined.
        #[arg(long)]
        rates: Option<PathBuf>,
        /// Joints whose equivalent body forces to report (OpenSim's joints_to_report_body_forces:
        /// names, comma separated, or ALL; default: the setup's): per joint the force and torque
        /// on its child at the child frame origin, in ground, whose power along the joint's
        /// mobilities is its generalized forces (Joint::calcEquivalentSpatialForce).
        #[arg(long, value_delimiter = ',')]
        body_force_joints: Vec<String>,
        /// Where the body forces go (default: the setup's output_body_forces_file, else
        /// body_forces_at_joints.sto, beside the output).
        #[arg(long)]
        body_forces: Option<PathBuf>,
        /// Output generalized forces (.sto).
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Static optimisation like OpenSim 4.6's StaticOptimization (AnalyzeTool): the coordinates
    /// are filtered and differentiated as the AnalyzeTool does (a coordinate the file lacks is
    /// held at 0), and per frame the muscle activations and actuator controls a minimise Σ|a|ᵖ
    /// (p = 2 by default) while their forces (a·F, F a muscle's active force at activation 1 with
    /// a rigid tendon, or an actuator's optimal force) give the tracked accelerations with gravity
    /// and the external loads (and the forces of links between bodies, which close loops), each
    /// control within its min/max_control — a convex programme solved to its optimum
    /// (OpenSim's IPOPT stops at its convergence criterion). Writes OpenSim's
    /// <NAME>_StaticOptimization_activation.sto and _force.sto into DIR. Exit 0 success, 1 some
    /// frame has no solution (its row is NaN) or, with --pia, the problem has none (nothing
    /// written), 2 error.
    So {
        /// The model (.osim).
        model: PathBuf,
        /// Coordinate trajectories (.mot or .sto), e.g. an inverse kinematics result.
        coordinates: PathBuf,
        /// An OpenSim AnalyzeTool setup with a StaticOptimization: its time range, cutoff,
        /// external loads, force_set_files (replace_force_set), step_interval and
        /// use_muscle_physiology are used (its model and coordinates file names are not).
        #[arg(long)]
        setup: Option<PathBuf>,
        #[command(flatten)]
        analyze: AnalyzeArgs,
        /// p of the objective Σ|a|ᵖ (> 1; default: the setup's, else 2).
        #[arg(long)]
        activation_exponent: Option<f64>,
        /// Another solution's activations (e.g. OpenSim's _activation.sto) to judge on this
        /// problem: how far its controls miss the constraints and bounds, and its Σ|a|ᵖ against ours.
        #[arg(long)]
        compare: Option<PathBuf>,
        /// The physiological inverse approach (De Groote et al. 2009) instead: every frame at once,
        /// consecutive activations bound by activation dynamics (τ_a, τ_d of each muscle), by the
        /// sum of squared controls or the largest muscle activation (min-max). Writes
        /// <NAME>_PhysiologicalInverse_activation.sto, _force.sto and _excitation.sto.
        #[arg(long, value_enum)]
        pia: Option<CriterionArgument>,
        /// With --pia: multiplies every muscle's activation and deactivation time constants.
        #[arg(long, default_value_t = 1.0)]
        time_constant_scale: f64,
        /// With --pia: muscles pull with their Hill model's tendon force in static equilibrium
        /// beside the compliant tendon (passive force included, fiber velocity neglected; thesis
        /// §3.2), linearised and solved again until it settles, instead of a·F₁ with a rigid
        /// tendon.
        #[arg(long)]
        compliant_tendons: bool,
        /// With --pia: skeleton dynamics as a penalty (the thesis' bi-objective form) — W times
        /// the sum of squared differences between the generalized forces and inverse dynamics
        /// (per N²·m² or N²) joins the criterion, instead of meeting inverse dynamics exactly.
        #[arg(long, value_name = "W")]
        moment_weight: Option<f64>,
    },
    /// Joint reaction loads like OpenSim 4.6's JointReaction analysis (AnalyzeTool): along the
    /// coordinates (filtered and differentiated as the AnalyzeTool does), every muscle and
    /// actuator exerts its force from the forces file (e.g. static optimisation's _force.sto,
    /// linearly interpolated), the accelerations are those the forces give with gravity and the
    /// external loads (forward dynamics, locks, couplers and links between bodies enforced), and
    /// each joint's load on its child (at the child frame origin) or parent (at the parent frame
    /// origin) is expressed in ground or a body. Writes OpenSim's <NAME>_JointReaction_ReactionLoads.sto into DIR.
    /// Exit 0 success, 2 error.
    Reaction {
        /// The model (.osim).
        model: PathBuf,
        /// Coordinate trajectories (.mot or .sto), e.g. an inverse kinematics result.
        coordinates: PathBuf,
        /// Each muscle's and actuator's force per time (.sto), a column per actuator by name;
        /// overrides the setup's forces_file.
        #[arg(long)]
        forces: Option<PathBuf>,
        /// An OpenSim AnalyzeTool setup with a JointReaction: its time range, cutoff, external
        /// loads, force_set_files (replace_force_set), forces_file, joint_names, apply_on_bodies,
        /// express_in_frame and step_interval are used.
        #[arg(long)]
        setup: Option<PathBuf>,
        #[command(flatten)]
        analyze: AnalyzeArgs,
        /// Joints to report, comma separated (default: the setup's, else all).
        #[arg(long, value_delimiter = ',')]
        joints: Vec<String>,
        /// child or parent: the body each load acts on, one for all joints or one per joint.
        #[arg(long, value_delimiter = ',')]
        on: Vec<String>,
        /// ground, a body's name, child or parent: the frame each load is expressed in, one for
        /// all joints or one per joint.
        #[arg(long = "in", value_delimiter = ',')]
        frames: Vec<String>,
    },
    /// Functional-scaling trials from isometric dynamometer contractions (thesis ch. 5 → 6): per
    /// contraction of SESSION.json, M3D along its motion with its load cell (as `dynamometer`
    /// computes it), averaged over the plateau around its peak (|M3D| ≥ the fraction of the peak)
    /// with the coordinates and the agonists' activations; one row per contraction in TRIALS/
    /// <set>_<direction>.mot and TRIALS/subject.json (the session's subject fields and the trial
    /// files), the folder `scale MODEL TRIALS/` reads. Exit 0 success, 2 error.
    Trials {
        /// The model (.osim) with the knee and the crank (as for `dynamometer`).
        model: PathBuf,
        /// The session (.json): `subject` (the subject file's fields: estimated_muscles,
        /// extension_agonists, flexion_agonists, agonist_activation, …), optional `crank`,
        /// `knee`, `hip`, `ankle` names, and `contractions`: per contraction `set`, `direction`
        /// (extension or flexion), `coordinates` (.mot), `load_cell` (ExternalLoads .xml) and
        /// optionally `activations` (.sto, a column per agonist); paths relative to the session.
        session: PathBuf,
        /// The plateau: the frames around the peak where |M3D| is at least this fraction of it.
        #[arg(long, default_value_t = 0.9)]
        plateau_fraction: f64,
        /// The largest turn of the crank over a plateau (degrees) an isometric contraction allows.
        #[arg(long, default_value_t = 2.0)]
        max_crank_motion: f64,
        /// Output folder (created if needed).
        #[arg(short, long)]
        output: PathBuf,
    },
    /// The knee moment from an extended dynamometer set-up (thesis ch. 5): 3D inverse dynamics of
    /// crank, shank and foot with a 6-D load cell in the crank gives M3D, the moment about the
    /// knee coordinate's (e.g. functional) axis; beside it the dynamometer's own moment Mdyn and
    /// Herzog's 2D estimate M2D with their Bland–Altman agreement, the axes' offset, the pad
    /// force's angle to the crank's normal, and M3D's sensitivity to the knee axis' pose and the
    /// bodies' masses and mass centers (table 5.1). The crank is a body of MODEL on a PinJoint to
    /// ground about the dynamometer's axis, its origin at the load cell. Writes the per-frame
    /// table (.sto) and prints the summary. Exit 0 success, 2 error.
    Dynamometer {
        /// The model (.osim) with the knee and the crank.
        model: PathBuf,
        /// Coordinate trajectories (.mot or .sto) with the crank's coordinate, e.g. an inverse
        /// kinematics result of the leg and crank markers.
        coordinates: PathBuf,
        /// An OpenSim ExternalLoads file (.xml) with its datafile: the load cell's wrench on the
        /// crank (an ExternalForce applied to the crank).
        #[arg(long)]
        load_cell: PathBuf,
        /// The crank's body.
        #[arg(long, default_value = "crank")]
        crank: String,
        /// The knee's coordinate.
        #[arg(long, default_value = "knee_angle_r")]
        knee: String,
        /// The load cell datafile's column with the dynamometer's moment (N·m, gravity-corrected,
        /// positive about the crank coordinate's axis).
        #[arg(long)]
        dynamometer_moment: Option<String>,
        /// -1 when that column is about the axis' other sense.
        #[arg(long, default_value = "1", allow_negative_numbers = true, value_parser = ["1", "-1"])]
        dynamometer_sign: String,
        /// Time range in seconds (clipped to the coordinates; each end goes to the frame at or
        /// before it).
        #[arg(long, num_args = 2, value_names = ["START", "END"], allow_negative_numbers = true)]
        time: Option<Vec<f64>>,
        /// Low-pass cutoff frequency for the coordinates, Hz (default: none).
        #[arg(long)]
        lowpass: Option<f64>,
        /// Sensitivity: the knee axis' turn about the shank's X and Y axes, degrees.
        #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
        perturb_axis_angle: f64,
        /// Sensitivity: the knee axis' shift along the shank's X and Y axes, m.
        #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
        perturb_axis_offset: f64,
        /// Sensitivity: the change of each body's mass, kg.
        #[arg(long, default_value_t = 0.25, allow_negative_numbers = true)]
        perturb_mass: f64,
        /// Sensitivity: the shift of each body's mass center along its X and Y axes, m.
        #[arg(long, default_value_t = 0.02, allow_negative_numbers = true)]
        perturb_mass_center: f64,
        /// Print the summary as JSON.
        #[arg(long)]
        json: bool,
        /// Also write the summary as JSON to this file.
        #[arg(long)]
        report: Option<PathBuf>,
        /// Output per-frame table (.sto).
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Predicted activations against EMG by cross-correlation (the thesis' ch. 7 check of inverse
    /// simulations): per muscle, Pearson's r between the prediction at its rows and the EMG
    /// envelope linearly interpolated there, at zero lag and at the best lag up to --max-lag
    /// (multiples of the prediction's median row step). Exit 0 success, 2 error.
    Emg {
        /// Predicted activations (.sto): columns named after muscles (`so`, `so --pia`) or
        /// OpenSim state names `/forceset/<muscle>/activation` (`forward`).
        predicted: PathBuf,
        /// EMG envelopes (.sto or .mot), one column per channel.
        emg: PathBuf,
        /// MUSCLE=CHANNEL pairs, comma separated (default: every predicted muscle the EMG file
        /// has a column for).
        #[arg(long, value_delimiter = ',')]
        pair: Vec<String>,
        /// Largest lag searched, s.
        #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
        max_lag: f64,
        /// JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Muscle-driven forward simulation along prescribed kinematics — the thesis' EMG-driven
    /// simulation (ch. 7), as OpenSim integrates a model whose coordinates are prescribed and whose
    /// muscles a PrescribedController excites: each muscle with an excitation column gets its
    /// activation (first-order dynamics, τ_a and τ_d of the muscle) and fiber length (fiber and
    /// tendon in balance) integrated along the coordinates' degree-5 GCV splines, excitations
    /// interpolated linearly (muscles with ignore_activation_dynamics, or all with --activations,
    /// take the table as their activation). States start at a = u(t₀) and the fiber length
    /// OpenSim's equilibrateMuscles gives. Writes
    /// <NAME>_states.sto (OpenSim's state names), _tendon_force.sto and
    /// _muscle_generalized_forces.sto (Σ F_t r per coordinate, named as inverse dynamics names its
    /// columns) into DIR; with --inverse-dynamics, prints per coordinate how far the muscles'
    /// generalized forces are from it (RMS, largest). Millard2012Equilibrium muscles (compliant
    /// or rigid tendons) and Thelen2003 muscles. Exit 0 success, 1 the integration failed (nothing
    /// written), 2 error.
    Forward {
        /// The model (.osim).
        model: PathBuf,
        /// Coordinate trajectories (.mot or .sto), e.g. an inverse kinematics result.
        coordinates: PathBuf,
        /// Excitations in [0, 1] (.sto): a column per driven muscle (e.g. processed EMG, or the
        /// _excitation.sto of `so --pia`); other columns are ignored.
        #[arg(long)]
        excitations: PathBuf,
        /// The --excitations table holds activations (e.g. EMG envelopes taken as activations, as
        /// the thesis' forward simulations are driven): each muscle's activation follows it, with
        /// no activation dynamics (OpenSim's ignore_activation_dynamics).
        #[arg(long)]
        activations: bool,
        /// Inverse-dynamics generalized forces (.sto, e.g. from `osim-tune id`) to compare with.
        #[arg(long)]
        inverse_dynamics: Option<PathBuf>,
        /// Time range in seconds, inside the coordinates (default: all of them).
        #[arg(long, num_args = 2, value_names = ["START", "END"], allow_negative_numbers = true)]
        time: Option<Vec<f64>>,
        /// Low-pass cutoff frequency for the coordinates, Hz (default: none).
        #[arg(long)]
        lowpass: Option<f64>,
        /// Relative and absolute error tolerance per state and step of the integrator.
        #[arg(long, default_value_t = 1e-8)]
        accuracy: f64,
        /// Prefix of the output files (default: the coordinates file's stem).
        #[arg(long)]
        name: Option<String>,
        /// Output folder (created if needed).
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Forward simulation like OpenSim 4.6's ForwardTool, from its setup: the model's forward
    /// dynamics integrated from the default state (assembled pose, default speeds, muscles at
    /// their default activation and fiber length) or the setup's states_file row at or before
    /// initial_time, muscles equilibrated when solve_for_equilibrium_for_auxiliary_states; every
    /// muscle excited and every other actuator controlled by the model's and the setup's
    /// ControlSetControllers and PrescribedControllers (their controls add; 0 without one),
    /// through its activation and fiber dynamics; the force-set files' actuators added, external
    /// loads applied; locked coordinates held, couplers exact, point, distance, point-on-line and
    /// weld constraints held at the acceleration level, the state projected back onto them
    /// after a step leaving them open by more than the tolerance. Dormand–Prince 5(4) at
    /// integrator_error_tolerance per state, steps of at most maximum_integrator_step_size, at
    /// most maximum_number_of_integrator_steps. Writes
    /// DIR/<name>_states.sto (every state after every step, OpenSim's labels),
    /// <name>_states_degrees.mot and <name>_controls.sto, and the tables of the AnalysisSet's
    /// analyses `analyze --setup` runs, formed from those states. A Ball, Free or ellipsoid
    /// joint's angles turn at the rates its angular velocity gives them. Exit 0 success, 1 the integration failed (nothing written), 2 error.
    Simulate {
        /// The model (.osim).
        model: PathBuf,
        /// The OpenSim ForwardTool setup (its other files relative to its folder).
        #[arg(long)]
        setup: PathBuf,
        /// Output folder (created if needed); existing files of the same names are replaced.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// OpenSim's residual reduction algorithm (RRATool) from its setup: the model's forces
    /// replaced by the setup's actuators (residuals on the pelvis, a CoordinateActuator per joint),
    /// with adjust_com_to_reduce_residuals the average residuals of inverse dynamics along the
    /// desired kinematics moving adjusted_com_body's mass center (and mass changes recommended),
    /// then CMC tracking of the desired kinematics (its CMC_Joint tasks, every 0.001 s the
    /// actuator forces minimising the weighted acceleration errors plus the actuators' squared
    /// stress, within the controls' bounds). Writes `<name>_states.sto`, `_controls.sto`,
    /// `_controls.xml`, `_pErr.sto`, `_Kinematics_q/u/dudt.sto`, `_Actuation_force/speed/power.sto`,
    /// `_avgResiduals.txt` and the adjusted model (output_model_file; only the mass center
    /// changes). Exit 0 success, 1 the tracking failed (nothing written), 2 error.
    Rra {
        /// The model (.osim).
        model: PathBuf,
        /// The OpenSim RRATool setup (its other files relative to its folder).
        #[arg(long)]
        setup: PathBuf,
        /// Output folder for the tables (created if needed); existing files of the same names are replaced.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// OpenSim's computed muscle control (CMCTool) from its setup: every cmc_time_window (default
    /// 0.01 s) the muscles' and actuators' forces that reach the CMC_Joint tasks' desired
    /// accelerations at the window's end (fast target: met exactly at the least Σ(f/F)²; slow:
    /// weighted least squares), the excitations that give those forces there (the muscles'
    /// activation and fiber states predicted over the window), and the model integrated under
    /// them; with muscles the tracking starts 0.03 s after initial_time, as OpenSim's
    /// computeInitialStates. Writes `<name>_states.sto`, `_controls.sto`, `_controls.xml`,
    /// `_pErr.sto`, `_Kinematics_q/u/dudt.sto` and `_Actuation_force/speed/power.sto`.
    /// Exit 0 success, 1 the tracking failed (nothing written), 2 error.
    Cmc {
        /// The model (.osim).
        model: PathBuf,
        /// The OpenSim CMCTool setup (its other files relative to its folder).
        #[arg(long)]
        setup: PathBuf,
        /// Output folder for the tables (created if needed); existing files of the same names are replaced.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Functional knee axis from a flexion–extension trial (thesis ch. 4): segment poses from
    /// the femur and tibia marker clusters, then GaL (Gamage & Lasenby) or SARA (Ehrig). Prints
    /// the axis in the lab frame of the trial's first frame and in both segment frames; with
    /// --epicondyles, its comparison with the transepicondylar axis. With --model the clusters
    /// are the model's markers (their body-frame locations), so the axis is in the model's body
    /// frames; --swap then replaces that knee joint by a PinJoint about the axis (same joint and
    /// coordinate names, the tibia pose at the reference angle kept) and writes -o.
    /// Exit 0 success, 2 error (e.g. too little rotation to identify an axis).
    Axis {
        /// Marker trajectories (.trc, any length unit) of a knee flexion–extension.
        trial: PathBuf,
        /// Femur cluster: ≥ 3 marker names, comma separated — or, with --model, one body name
        /// (every model marker on it that the trial has).
        #[arg(long, value_delimiter = ',', required = true)]
        femur: Vec<String>,
        /// Tibia cluster, as --femur.
        #[arg(long, value_delimiter = ',', required = true)]
        tibia: Vec<String>,
        #[arg(long, value_enum, default_value_t = AxisMethodArgument::Gal)]
        method: AxisMethodArgument,
        /// Segment poses per frame by least squares, or by a Kalman smoother over the trial.
        #[arg(long, value_enum, default_value_t = PoseArgument::LeastSquares)]
        poses: PoseArgument,
        /// Lateral and medial epicondyle markers (femur): compare with the transepicondylar axis.
        #[arg(long, value_delimiter = ',', num_args = 1, value_names = ["LAT,MED"])]
        epicondyles: Option<Vec<String>>,
        /// The model whose markers define the clusters (and whose knee --swap replaces).
        #[arg(long)]
        model: Option<PathBuf>,
        /// The joint to replace, e.g. knee_r (needs --model and -o).
        #[arg(long, requires_all = ["model", "output"])]
        swap: Option<String>,
        /// Knee angle (degrees) at which the swapped joint keeps the tibia's pose (default: the
        /// coordinate's default value).
        #[arg(long, allow_negative_numbers = true, requires = "swap")]
        reference_angle: Option<f64>,
        /// The model with the swapped knee (.osim).
        #[arg(short, long, requires = "swap")]
        output: Option<PathBuf>,
        /// Print the result as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Print every property as `PATH = VALUE`, one per line, numbers in shortest form: a stable
    /// text form of a document for `git diff` (use as diff.textconv; see README).
    Flatten {
        document: PathBuf,
    },
    /// Draw columns of OpenSim tables (.sto, .mot: an IK motion, ID moments, SO activations, a
    /// CMC or RRA result) against time, or against --x COLUMN, as an SVG chart: one colour per
    /// column, one line style per table (solid, dashed, dots), so the same column of two results
    /// — ours and OpenSim's — overlays. Values are drawn as the files hold them (degrees stay
    /// degrees).
    Plot {
        /// The tables; each must hold every named column.
        #[arg(required = true)]
        tables: Vec<PathBuf>,
        /// The columns to draw, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        columns: Vec<String>,
        /// The column on the horizontal axis (default: time).
        #[arg(long)]
        x: Option<String>,
        /// The chart's title (default: the tables' file names).
        #[arg(long)]
        title: Option<String>,
        /// The vertical axis' label (default: the column's name, or "value" for several).
        #[arg(long)]
        y_label: Option<String>,
        /// The chart to write (.svg).
        #[arg(short, long)]
        output: PathBuf,
    },
}

/// `--method` of `scale` (functional scaling).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ScaleMethodArgument {
    /// The thesis' method: feasible sets, hot start, constrained NLP.
    Functional,
    /// Garner & Pandy (2003): least squares over [L̃m_min, L̃m_max].
    GarnerPandy,
}

/// `--method` of `axis`.
/// The physiological inverse approach's criterion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum CriterionArgument {
    /// Σ of squared controls over all frames.
    SumOfSquares,
    /// The largest muscle activation over the motion.
    MinMax,
}

impl From<CriterionArgument> for crate::analysis::Criterion {
    fn from(argument: CriterionArgument) -> Self {
        match argument {
            CriterionArgument::SumOfSquares => crate::analysis::Criterion::SumOfSquares,
            CriterionArgument::MinMax => crate::analysis::Criterion::MinMax,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum AxisMethodArgument {
    /// Gamage & Lasenby: circles of the tibia markers in the femur frame and of the femur markers in
    /// the tibia frame, combined.
    Gal,
    /// Ehrig's symmetrical axis of rotation approach.
    Sara,
}

/// `--poses` of `axis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PoseArgument {
    /// Each frame's least-squares rigid fit (Söderkvist).
    LeastSquares,
    /// A Rauch–Tung–Striebel smoother, constant 4th derivative (thesis default settings).
    Kalman,
}

/// The AnalyzeTool's flags `so` and `reaction` share.
#[derive(Debug, clap::Args)]
pub struct AnalyzeArgs {
    /// An OpenSim ExternalLoads file (.xml) with its datafile; overrides the setup's.
    #[arg(long)]
    pub external_loads: Option<PathBuf>,
    /// ForceSet files of Coordinate-, Point- and TorqueActuators (residuals, reserves) added to
    /// the model's muscles and actuators, comma separated; override the setup's.
    #[arg(long, value_delimiter = ',')]
    pub actuators: Vec<PathBuf>,
    /// Time range in seconds (each end goes to the row at or before it; default: the setup's,
    /// else `reaction`'s forces file's times, else all rows).
    #[arg(long, num_args = 2, value_names = ["START", "END"], allow_negative_numbers = true)]
    pub time: Option<Vec<f64>>,
    /// Low-pass cutoff frequency for the coordinates, Hz (default: the setup's, else none).
    #[arg(long)]
    pub lowpass: Option<f64>,
    /// Analyse the first and last rows and every row whose index is a multiple of N.
    #[arg(long)]
    pub step_interval: Option<usize>,
    /// COORDINATES is an OpenSim states file (as a setup's states_file, which implies this):
    /// its coordinates and speeds are used as they are (not filtered), the accelerations
    /// splined from the speeds, as OpenSim's AnalyzeTool does.
    #[arg(long)]
    pub states: bool,
    /// Prefix of the output files (default: the setup's name, else the coordinates file's stem).
    #[arg(long)]
    pub name: Option<String>,
    /// Output folder (created if needed).
    #[arg(short, long)]
    pub output: PathBuf,
}
