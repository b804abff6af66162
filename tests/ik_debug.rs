mod common;
use osim_tune::io::osim::OsimDocument;
use osim_tune::io::table::{MarkerTable, StorageTable};
use osim_tune::mechanics::{Motion, Multibody};
use osim_tune::model::ModelSpec;
use osim_tune::solvers::*;
use osim_tune::validation::ik::*;

#[test]
fn debug() {
    let case = IkCase::subject01_walk1(&common::root());
    let spec = ModelSpec::read(&OsimDocument::read(&case.model).unwrap()).unwrap();
    let mb = Multibody::new(&spec).unwrap();
    let trial = MarkerTable::read(&case.trial).unwrap();
    let (tasks, range) = read_setup_tasks(&case.setup).unwrap();
    let ik = InverseKinematics::new(&mb, &trial, &case.trial, &tasks, IkSettings::default()).unwrap();
    let mut zero = IkSettings::default();
    zero.convergence.max_iterations = 0;
    let ik0 = InverseKinematics::new(&mb, &trial, &case.trial, &tasks, zero).unwrap();
    let golden = Motion::from_table(&StorageTable::read(&case.motion).unwrap(), &case.motion, &mb, false).unwrap();
    let mut ws = ik.workspace();
    let mut q = ik.initial_pose();
    for (row, f) in ik.frames(range).unwrap().enumerate() {
        let s = ik.solve_frame(f, &mut q, &mut ws).unwrap();
        let mut qg = golden.pose(row).to_vec();
        let g = ik0.solve_frame(f, &mut qg, &mut ws).unwrap();
        let mut grad = vec![0.0; qg.len()];
        let h = 1e-6;
        for c in 0..qg.len() {
            let mut qp = golden.pose(row).to_vec(); qp[c] += h;
            let mut qm = golden.pose(row).to_vec(); qm[c] -= h;
            let fp = ik0.solve_frame(f, &mut qp, &mut ws).unwrap().objective;
            let fm = ik0.solve_frame(f, &mut qm, &mut ws).unwrap().objective;
            grad[c] = (fp - fm) / (2.0 * h);
        }
        let gnorm = grad.iter().map(|g| g * g).sum::<f64>().sqrt();
        let xnorm = golden.pose(row).iter().map(|g| g * g).sum::<f64>().sqrt();
        if row % 10 == 0 { println!("   |g|={gnorm:.3e} |x|={xnorm:.3} ratio={:.3e} gmax_at={}", gnorm / xnorm.max(1.0), grad.iter().enumerate().max_by(|a, b| a.1.abs().total_cmp(&b.1.abs())).unwrap().0); }
        if row % 10 == 0 || s.status != LeastSquaresStatus::Converged && row < 5 {
            println!("{row} {:?} it={} F={:.12e} Fgold={:.12e} diff={:.3e}", s.status, s.iterations, s.objective, g.objective, g.objective - s.objective);
        }
    }
}

#[test]
fn versus_tight() {
    let root = common::root();
    for file in ["/tmp/ikexp/acc8.mot", "/tmp/ikexp/acc10.mot"] {
        let mut case = IkCase::subject01_walk1(&root);
        case.motion = file.into();
        case.errors = file.replace(".mot", "_ik_marker_errors.sto").into();
        let c = compare_ik(&case, IkFrames::Trial).unwrap();
        println!("== {file}");
        for d in &c.coordinates { println!("{:<20} {:.3e} at {}", d.name, d.worst, d.at); }
        println!("rms excess {:.3e} at {} improvement {:.3e}", c.rms_excess, c.rms_excess_at, c.rms_improvement);
    }
}
