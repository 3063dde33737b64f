//! scratch: detectability of true effects under replay modes
use shoal_model::effects::{EffectInstance, Effects, by_name_form};
use shoal_model::presets;
use shoal_model::rigid_body::Environment;
use shoal_model::vehicle::VehicleModel;
use shoal_sysid::evaluate::anchoring::Horizon;
use shoal_sysid::evaluate::dataset::{DataOptions, Dataset};
use shoal_sysid::evaluate::evaluation::Evaluation;
use shoal_sysid::evaluate::open_loop::ReplayOptions;
use shoal_sysid::evaluate::open_loop::anchors::{Anchor, OBSERVER_S};
use shoal_testkit::closed_loop::cases;
use shoal_testkit::mission::Disturbance;

fn gains(b: &Evaluation, t: &Evaluation) -> String {
    let mut out = String::new();
    let mut sum = 0.0; let mut n = 0.0;
    for (k, mb) in &b.metrics {
        let mt = &t.metrics[k];
        let g = 100.0 * (1.0 - mt.rmse / mb.rmse);
        let ge = 100.0 * (1.0 - mt.rmse_est / mb.rmse_est);
        out += &format!(" {}:{:.1}/{:.1}", k.label(), ge, g);
        sum += g; n += 1.0;
    }
    format!("mean val gain {:.2} |{}", sum / n, out)
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let len: f64 = args[1].parse().unwrap();
    for c in cases(len) {
        let h = &c.hidden;
        let truth = match h.first().map(|h| h.form.name) {
            Some("battery_sag/quadratic") => vec![(("battery_sag", "power"), vec![h[0].values[0] * 1e4, 2.0])],
            Some("thrust_gain/per_thruster") => { let k = 1.0 + h[0].values[0]; let r = h[0].values[1]; vec![(("thrust_gain", "per_thruster"), vec![k, k * (1.0 + r), k * (1.0 - r)])] }
            _ => continue,
        };
        let base = presets::uauv2();
        let model = VehicleModel::new(base.clone(), 1000.0);
        let tm = VehicleModel::with_effects(base.clone(), Effects::new(truth.iter().map(|((e, f), p)| EffectInstance { effect: by_name_form(e, Some(f)).unwrap(), params: p.clone() }).collect()), 1000.0);
        let run = c.run(&Disturbance::default());
        for mode in ["open2", "closed", "closed2", "closed5", "closed10", "closed30"] {
            let mut ds = Dataset::new(&base, Environment { density: 1000.0, ..Default::default() }, vec![run.clone()], vec![], &DataOptions { replay: ReplayOptions { dt: 0.02, ..Default::default() }, ..Default::default() }).unwrap();
            match mode {
                "open2" => { ds.anchor(Horizon::Every(2.0), &model); }
                _ => {
                    ds.anchor(Horizon::Closed, &model);
                    if let Ok(hz) = mode.trim_start_matches("closed").parse::<f64>() {
                        for rd in &mut ds.runs { rd.init.anchors = Anchor::every(&rd.run, hz, 0.02); rd.init.filter = Anchor::every(&rd.run, OBSERVER_S, 0.02); }
                    }
                }
            }
            let b = ds.evaluate(&model);
            let t = ds.evaluate(&tm);
            println!("{} {:<9} {}", c.name, mode, gains(&b, &t));
        }
    }
}
