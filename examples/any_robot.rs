//! Any parallel robot from a file: loads a robot file, then prints its working modes, its
//! assembly modes, the screw Jacobians and the three singularity margins at a pose.
//!
//! Run: `cargo run --example any_robot -- [examples/robots/<file>.toml] [task coordinates…]`
//! (default: the 3-PRS at z = 0.5 m, tilt (0.05, −0.02) rad).
#![allow(clippy::print_stdout)]

use pkm_robot_file::{EnumerationSettings, RobotModel};

type Result<T> = std::result::Result<T, Box<dyn std::error::Error>>;

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args.first().map_or_else(
        || {
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/examples/robots/three_prs.toml"
            )
            .to_string()
        },
        Clone::clone,
    );
    let robot = RobotModel::from_toml(&std::fs::read_to_string(&path)?)?;
    let x: Vec<f64> = if args.len() > 1 {
        args[1..]
            .iter()
            .map(|a| a.parse())
            .collect::<std::result::Result<_, _>>()?
    } else if path.ends_with("three_prs.toml") {
        vec![0.5, 0.05, -0.02]
    } else {
        robot.home_task()
    };
    println!("{} ({path})", robot.name());
    println!("task {:?} = {x:?}", robot.task_names());
    println!("leg solvers {:?}", robot.leg_solvers());

    println!(
        "\nworking modes (leg i's branch, + or -, as a study's `modes` names it; home mode {}):",
        robot.mode_label(robot.home_mode())
    );
    for mode in robot.working_modes() {
        let label = robot.mode_label(mode);
        match robot.inverse_kinematics(&x, mode) {
            Ok(q) => println!("  {label}: q = {:?}", q.as_slice()),
            Err(e) => println!("  {label}: {e}"),
        }
    }

    let config = robot.inverse_kinematics_configuration(&x, robot.home_mode())?;
    let q = robot.actuators_of(&config);
    println!("\nfull pose in the home mode: {:?}", config.pose());
    let modes = robot.assembly_modes(q.as_slice(), &EnumerationSettings::default())?;
    println!("assembly modes at q = {:?}: {}", q.as_slice(), modes.len());
    for m in &modes {
        println!(
            "  task {:?}, home label {:?}, margins inverse {:.3e} direct {:.3e}",
            m.task, m.home_label, m.margins.inverse, m.margins.direct
        );
    }

    let jac = robot.screw_jacobians(&config)?;
    println!("\nJ = D⁻¹ J_a T (q̇ = J ẋ):{}", jac.j);
    println!("J_a (actuation wrenches [f; m_O]):{}", jac.j_a);
    println!(
        "J_c (constraint wrenches, {} rows):{}",
        jac.j_c.nrows(),
        jac.j_c
    );
    println!("D = {:?}", jac.d.as_slice());
    let margins = robot.singularity_margins(&config)?;
    println!(
        "singularity margins (L = {} m): inverse {:.4}, direct {:.4}, constraint {:?}",
        robot.characteristic_length(),
        margins.inverse,
        margins.direct,
        margins.constraint
    );
    Ok(())
}
