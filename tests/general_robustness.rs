//! Robustness of the general problem (P) (issue 30, items 3, 4, 7 and 14): no non-finite number
//! reported as an answer, a stiff drift integrated stably (the answer converges under grid
//! refinement, against closed forms) or refused naming the grid, a documented limit on the
//! faces with an analysis that scales with them, and normals of extreme length accepted.

mod common;

use crawlopt::api::{self, GeneralPmSettings};
use crawlopt::integrate::{DriftStep, GeneralMethod, GeneralSimOptions};
use crawlopt::io::GeneralFile;
use crawlopt::model::general::MAX_FACES;

/// The paper's one-link problem in general form (J* = 3 for the bang-bang input below).
const ONE_LINK: &str = r#"
[sweeping_process]
normals = [[1.0], [-1.0]]
offsets = [1.0, 1.0]
[dynamics]
B = [[1.0]]
[control]
lower = [-1.0]
upper = [1.0]
zero_mean = true
[objective]
face_weights = [0.5, 0.5]
[problem]
period = 10.0
[input]
kind = "piecewise_constant"
times = [0.0, 5.0]
values = [[1.0], [-1.0]]
"#;

/// The issue's stiff example: the box [-1, 1]^2, A = diag(-1e3, 1e3), the weight on x1 <= 1.
const STIFF: &str = r#"
[sweeping_process]
normals = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]]
offsets = [1.0, 1.0, 1.0, 1.0]
[dynamics]
A = [[-1000.0, 0.0], [0.0, 1000.0]]
B = [[1.0, 0.0], [0.0, 1.0]]
[control]
lower = [-1.0, -1.0]
upper = [1.0, 1.0]
zero_mean = true
[objective]
face_weights = [1.0, 0.0, 0.0, 0.0]
[problem]
period = 10.0
[input]
kind = "piecewise_constant"
times = [0.0, 2.5, 5.0, 7.5]
values = [[1.0, 0.5], [1.0, -0.5], [-1.0, -0.5], [-1.0, 0.5]]
"#;

fn file(text: &str) -> GeneralFile {
    GeneralFile::parse(text).unwrap()
}

fn steps(n: usize) -> GeneralSimOptions {
    GeneralSimOptions {
        steps_per_period: n,
        ..GeneralSimOptions::DEFAULT
    }
}

fn j_of(text: &str, n: usize) -> f64 {
    api::simulate_general(&file(text), &steps(n))
        .unwrap()
        .simulation
        .objective
        .unwrap()
}

fn err_of<T: std::fmt::Debug>(r: crawlopt::Result<T>) -> String {
    r.unwrap_err().to_string()
}

#[test]
fn weights_whose_product_overflows_are_refused_naming_the_field() {
    // Item 3: [1e308, 1e308] summed times T overflows: refused up front (it printed J = inf).
    let huge = ONE_LINK.replace("[0.5, 0.5]", "[1e308, 1e308]");
    let e = err_of(api::simulate_general(&file(&huge), &steps(100)));
    assert!(e.starts_with("objective.face_weights"), "{e}");
    let e = err_of(api::analyze_general(&file(&huge)));
    assert!(e.starts_with("objective.face_weights"), "{e}");
    // A cost weight whose int f2 overflows over U.
    let cost = ONE_LINK.replace(
        "face_weights = [0.5, 0.5]",
        "face_weights = [0.5, 0.5]\ncost = { kind = \"quadratic\", weight = 1e308 }",
    );
    let e = err_of(api::simulate_general(&file(&cost), &steps(100)));
    assert!(e.starts_with("objective.cost.weight"), "{e}");
    // Weights that pass the check (their sum times T is finite) but whose reactions (1e10 on
    // a held face, B = 1e10) take int f1 past the range: the computed number is refused, by
    // both integrators, naming what overflowed (no answer with J = inf or null).
    let fast = ONE_LINK
        .replace("[0.5, 0.5]", "[1e300, 1e300]")
        .replace("B = [[1.0]]", "B = [[1e10]]");
    for method in [GeneralMethod::Auto, GeneralMethod::CatchingUp] {
        let opts = GeneralSimOptions {
            method,
            ..steps(100)
        };
        let e = err_of(api::simulate_general(&file(&fast), &opts));
        assert!(
            e.starts_with("int f1(eta)") && e.contains("overflow"),
            "{e}"
        );
    }
    // The same reactions with unit weights are an answer.
    let ok = ONE_LINK.replace("B = [[1.0]]", "B = [[1e10]]");
    assert!(j_of(&ok, 100).is_finite());
}

#[test]
fn a_stiff_drift_converges_under_refinement_to_the_closed_form() {
    // Item 4, the issue's example: x1' = -1000 x1 + u1 stays within 1e-3 of 0 and never
    // reaches x1 = 1, so J = 0 exactly; the explicit step gave 4900, 4000 and 0 at M = 100,
    // 1000, 100000. The semi-implicit step gives 0 on every grid.
    for m in [10, 100, 1000, 10_000] {
        let j = j_of(STIFF, m);
        assert!(j.abs() < 1e-12, "M = {m}: J = {j}");
    }
    // The faces x2 = +-1 held by the unstable x2' = 1000 x2 + u2: the reaction is
    // 1000 + u2 on the face the orbit sits on, J = int (1000 + u2) = 1e4 on every grid (the
    // explicit growing part gives the normal component of g exactly on a held face).
    let held = STIFF.replace("[1.0, 0.0, 0.0, 0.0]", "[0.0, 1.0, 0.0, 1.0]");
    for m in [10, 100, 1000, 10_000] {
        let j = j_of(&held, m);
        assert!((j - 1e4).abs() < 1e-6, "M = {m}: J = {j}");
    }
    // A transient at the stiff rate: C = [-1, 1], x' = -1000 x + 1500 u, u = +1 then -1.
    // From -1 the state reaches 1 at t* = ln(5)/1000, then is held with reaction
    // -1000 + 1500 = 500 until T/2: J = 500 (5 - ln(5)/1000). The errors shrink as h does
    // (first order, faster once h resolves the transient) and the coarse grids are already
    // within a per cent.
    let transient = ONE_LINK
        .replace("B = [[1.0]]", "A = [[-1000.0]]\nB = [[1500.0]]")
        .replace("[0.5, 0.5]", "[1.0, 0.0]");
    let exact = 500.0 * (5.0 - 5f64.ln() / 1000.0);
    let errors: Vec<f64> = [1000, 10_000, 100_000]
        .iter()
        .map(|&m| (j_of(&transient, m) - exact).abs())
        .collect();
    assert!(errors[0] < 1e-2 * exact, "{errors:?}");
    assert!(errors[2] < 0.1, "{errors:?}");
    for w in errors.windows(2) {
        assert!(w[1] < 0.5 * w[0], "errors do not shrink: {errors:?}");
    }
    // A fast rotation (|K| = 300, explicit in the semi-implicit step) is refused on grids
    // where forward Euler's spurious growth exp(T h |K|^2 / 2) over a period exceeds e: 6000
    // steps pass the stability limit h |K| <= 2 (with |K| = 1e3, 50000 steps reached no
    // periodic regime in 5000 periods); the message gives the steps needed (T^2 |K|^2 / 2 =
    // 4.5e6), and where no grid of at most 1e7 steps has them, says to scale A down.
    let rot = STIFF.replace(
        "A = [[-1000.0, 0.0], [0.0, 1000.0]]",
        "A = [[-1.0, 300.0], [-300.0, -1.0]]",
    );
    let e = err_of(api::simulate_general(&file(&rot), &steps(6000)));
    assert!(
        e.starts_with("steps_per_period")
            && e.contains("exp(T h |K|^2 / 2)")
            && e.contains("needs at least 4.5")
            && e.contains("e6 steps"),
        "{e}"
    );
    let e = err_of(api::simulate_general(
        &file(&rot.replace("300.0", "1000.0")),
        &steps(6000),
    ));
    assert!(e.contains("scale dynamics.A down"), "{e}");
    // The paper's explicit step (which P_m uses) refuses the grid beyond its stability limit,
    // naming it and the steps it needs.
    let opts = GeneralSimOptions {
        drift: DriftStep::Explicit,
        ..steps(1000)
    };
    let e = err_of(api::simulate_general(&file(&transient), &opts));
    assert!(
        e.starts_with("steps_per_period") && e.contains("needs at least 5e3 steps"),
        "{e}"
    );
    let opts = GeneralSimOptions {
        drift: DriftStep::Explicit,
        ..steps(100_000)
    };
    let j = api::simulate_general(&file(&transient), &opts)
        .unwrap()
        .simulation
        .objective
        .unwrap();
    assert!((j - exact).abs() < 0.1, "{j}");
}

#[test]
fn p_m_refuses_a_step_beyond_the_explicit_limit() {
    // Item 4: A = 1e12 returned 5e12 from `optimize` and `--method local`; P_m's explicit step
    // at h = 10/2^m is refused naming m (beyond the largest m here).
    let stiff = STIFF.replace("1000.0", "1e12");
    let e = err_of(api::optimize_general(
        &file(&stiff),
        &GeneralPmSettings::default(),
        crawlopt::api::Hooks::default(),
    ));
    assert!(e.starts_with("m:") && e.contains("stability limit"), "{e}");
    let e = err_of(api::optimize_general_local(
        &file(&stiff),
        &api::GeneralLocalSettings::default(),
        api::Hooks::default(),
    ));
    assert!(e.starts_with("m:") && e.contains("stability limit"), "{e}");
    // A = 1e300 (the KKT residual of 1e296 reported with exit 0): the simulator's growing
    // part is beyond its precision limit on any grid, refused naming the grid.
    let e = err_of(api::simulate_general(
        &file(&STIFF.replace("1000.0", "1e300")),
        &steps(1000),
    ));
    assert!(e.starts_with("steps_per_period"), "{e}");
    // Within the limit (A = -0.5 I on P_3, h |A| = 0.625 <= 2) P_m solves as before.
    let mild = STIFF.replace("-1000.0", "-0.5").replace("1000.0", "-0.5");
    let s = GeneralPmSettings {
        m: 3,
        ..Default::default()
    };
    assert!(api::optimize_general(&file(&mild), &s, crawlopt::api::Hooks::default()).is_ok());
}

/// A regular polygon of `k` faces around the origin (inradius 1), `f1` by reaction weights.
fn polygon(k: usize, extra: &str) -> String {
    let normals: Vec<String> = (0..k)
        .map(|j| {
            let a = std::f64::consts::TAU * j as f64 / k as f64;
            format!("[{:?}, {:?}]", a.cos(), a.sin())
        })
        .collect();
    format!(
        "[sweeping_process]\nnormals = [{}{extra}]\noffsets = [{}{}]\n[dynamics]\n\
         B = [[1.0, 0.0], [0.0, 1.0]]\n[control]\nlower = [-1.0, -1.0]\nupper = [1.0, 1.0]\n\
         zero_mean = true\n[objective]\nreaction_weights = [1.0, 0.0]\n[problem]\nperiod = 10.0\n\
         [input]\nkind = \"piecewise_constant\"\ntimes = [0.0, 5.0]\n\
         values = [[1.0, 0.0], [-1.0, 0.0]]\n",
        normals.join(", "),
        vec!["1.0"; k].join(", "),
        if extra.is_empty() { "" } else { ", 2.0, 1.0" },
    )
}

#[test]
fn faces_are_limited_and_redundancy_needs_no_lp_per_face() {
    // Item 7: beyond MAX_FACES the file is refused naming the field.
    let e = err_of(api::analyze_general(&file(&polygon(MAX_FACES + 1, ""))));
    assert!(e.starts_with("sweeping_process.normals"), "{e}");
    assert!(e.contains(&MAX_FACES.to_string()), "{e}");
    // At the limit: analysed (each face shown needed by a ray from the centre, no LP each) and
    // simulated. A redundant face x <= 2 and a duplicate of face 1 are still found (by LP).
    let text = polygon(MAX_FACES - 2, ", [1.0, 0.0], [1.0, 0.0]");
    let a = api::analyze_general(&file(&text)).unwrap();
    assert_eq!(a.geometry.faces, MAX_FACES);
    assert_eq!(a.geometry.redundant_faces, vec![1, MAX_FACES - 1]);
    assert!(a.geometry.bounded && a.failure.is_none());
    let s = api::simulate_general(&file(&text), &steps(100)).unwrap();
    assert!(s.simulation.objective.unwrap().is_finite());
}

#[test]
fn normals_of_extreme_length_are_scaled_and_accepted() {
    // Item 14: [1e308] and [1e-300] are non-zero and finite; after dividing each row by its
    // length C is [-1, 1], the one-link problem (J = (T - 2 (b - a)) / 2 = 3 for this input).
    let scaled = ONE_LINK.replace(
        "normals = [[1.0], [-1.0]]\noffsets = [1.0, 1.0]",
        "normals = [[1e308], [-1e-300]]\noffsets = [1e308, 1e-300]",
    );
    assert_ne!(scaled, ONE_LINK);
    let j = j_of(&scaled, 1000);
    assert!((j - 3.0).abs() < 1e-12, "{j}");
    // A row whose scaled offset overflows says so, naming the offset.
    let over = ONE_LINK.replace(
        "normals = [[1.0], [-1.0]]\noffsets = [1.0, 1.0]",
        "normals = [[1e-300], [-1.0]]\noffsets = [1e10, 1.0]",
    );
    let e = err_of(api::analyze_general(&file(&over)));
    assert!(
        e.starts_with("sweeping_process.offsets[1]") && e.contains("overflows"),
        "{e}"
    );
    // A zero normal is refused as zero; one whose length overflows says that.
    let zero = ONE_LINK.replace("[[1.0], [-1.0]]", "[[0.0], [-1.0]]");
    let e = err_of(api::analyze_general(&file(&zero)));
    assert!(
        e.contains("must be non-zero") && !e.contains("finite"),
        "{e}"
    );
    let two = STIFF.replace(
        "[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0]",
        "[1.7e308, 1.7e308], [0.0, 1.0], [-1.0, 0.0]",
    );
    let e = err_of(api::analyze_general(&file(&two)));
    assert!(
        e.starts_with("sweeping_process.normals[1]") && e.contains("length overflows"),
        "{e}"
    );
}

#[test]
fn p_m_at_extreme_scales_names_the_field() {
    // Item 14: "big-M of P_m (slack): HiGHS ended with status unbounded" and "HiGHS refused the
    // model" named no field; data beyond P_m's solver range are refused up front naming it.
    let huge = ONE_LINK
        .replace("offsets = [1.0, 1.0]", "offsets = [1e300, 1e300]")
        .replace("period = 10.0", "period = 1e301")
        .replace("times = [0.0, 5.0]", "times = [0.0, 5e300]");
    let tiny = ONE_LINK
        .replace("offsets = [1.0, 1.0]", "offsets = [1e-300, 1e-300]")
        .replace("period = 10.0", "period = 1e-299")
        .replace("times = [0.0, 5.0]", "times = [0.0, 5e-300]");
    let fast = ONE_LINK.replace("B = [[1.0]]", "B = [[1e25]]");
    let heavy = ONE_LINK.replace("[0.5, 0.5]", "[1e30, 1e30]");
    for (text, field) in [
        (&huge, "sweeping_process.offsets"),
        (&tiny, "sweeping_process.offsets"),
        (&fast, "dynamics.B"),
        (&heavy, "objective.face_weights"),
    ] {
        let f = file(text);
        let e = err_of(api::optimize_general(
            &f,
            &GeneralPmSettings::default(),
            crawlopt::api::Hooks::default(),
        ));
        assert!(e.starts_with(field) && e.contains("P_m's solver"), "{e}");
        let e = err_of(api::optimize_general_local(
            &f,
            &api::GeneralLocalSettings::default(),
            api::Hooks::default(),
        ));
        assert!(e.starts_with(field) && e.contains("P_m's solver"), "{e}");
    }
}

/// A polytope U and a phase gait with a short phase: the MILP holds `G U_j <= h tau_j` to its
/// feasibility tolerance only, so the control `U_j / tau_j` of a phase of `tau` near `1e-8`
/// lay 2.3 outside a row of U and the answer was refused with exit 2 ("phase controls.values[2]:
/// lies outside U"). The control is now projected into U before the replay: the answer is
/// given (the idle gait is feasible, so `J >= 0` up to rounding), within its bound, every
/// control in U, and the written file reads back and certifies.
#[test]
fn a_short_phases_control_is_moved_into_a_polytope_u() {
    let dir = tempfile::tempdir().unwrap();
    let model = common::write(
        dir.path(),
        "polytope_u.toml",
        "[sweeping_process]\n\
         normals = [[0.9997372281088599, 0.02292323566195161], [0.1387449886130504, \
         0.9903281416453662], [-0.9949380672463262, 0.10049001116601047], \
         [0.0035330825904135534, -0.9999937586442273]]\n\
         offsets = [0.7552912262686192, 0.838851581068972, 0.6139129123927302, \
         0.7351895113842175]\n\
         [dynamics]\nB = [[0.8879897982475538, 0.5590796910868205], [0.43021727930404396, \
         -0.02241435445329598]]\n\
         [control]\nG = [[1.9753671107542528, -0.07740368977463759], [-0.30987330566396687, \
         0.5999056494386116], [-0.7746520746929578, -1.5640900825725343]]\n\
         h = [0.3919819644461409, 0.9603297044966883, 0.9791598208106451]\nzero_mean = true\n\
         [objective]\nface_weights = [0.45224622835758055, -0.13510819605910684, \
         -0.20444739189411087, 0.03429418746432067]\n\
         cost = { kind = \"quadratic\", weight = 0.0984788 }\n\
         [problem]\nperiod = 4.028844916223908\n",
    );
    let v = common::optimize_json(&model, &["--method", "phase", "--phases", "3"]);
    let j = v["objective"].as_f64().unwrap();
    let bound = v["certificate"]["bound"].as_f64().unwrap();
    assert!(j >= -1e-9 && bound >= j - 1e-9, "J = {j}, bound {bound}");
    let g = [
        [1.9753671107542528, -0.07740368977463759, 0.3919819644461409],
        [-0.30987330566396687, 0.5999056494386116, 0.9603297044966883],
        [-0.7746520746929578, -1.5640900825725343, 0.9791598208106451],
    ];
    for u in v["solution"]["controls"].as_array().unwrap() {
        let u: Vec<f64> = u
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_f64().unwrap())
            .collect();
        for r in &g {
            assert!(r[0] * u[0] + r[1] * u[1] <= r[2] + 1e-9, "{u:?} outside U");
        }
    }
    common::certify_written(dir.path(), &v);
}

/// A general file that is a crawler's chain (three blocks, per-link stiffness and friction, in
/// the variables of `crawler_as_general`): the chain's phase formulation returned a rate
/// 5.4e-10 above its bound of 4.4535544824622555, within the crawler's tolerance but not the
/// replay's, and the answer was refused with exit 2 ("phase controls.values[5]: lies outside
/// U"). The chain's controls are now clipped into U before the replay: the answer is the
/// crawler's own optimum among three slip phases, 2.496835698 (`optimize` of the crawler file
/// with `--phases 3`), with every control in U.
#[test]
fn a_chain_gaits_rate_at_its_bound_by_rounding_is_clipped_into_u() {
    let dir = tempfile::tempdir().unwrap();
    let model = common::write(
        dir.path(),
        "chain_box.toml",
        "[sweeping_process]\n\
         normals = [[-0.8141151387263864, 0.0], [0.8141151387263864, -0.0], \
         [0.8141151387263864, -1.608748299060648], [-0.8141151387263864, 1.608748299060648], \
         [0.0, 1.608748299060648], [-0.0, -1.608748299060648]]\n\
         offsets = [1.645661928464921, 2.0732187267605835, 0.8826035386091325, \
         2.7805754045296704, 1.2431526306379115, 3.2605317289742963]\n\
         [dynamics]\nB = [[1.228327483953209, 0.0], [0.0, 0.6216012788227359]]\n\
         [control]\nlower = [-0.2307750432594322, -4.4535544824622555]\n\
         upper = [0.2307750432594322, 4.4535544824622555]\nzero_mean = true\n\
         [objective]\nface_weights = [0.40944249465106974, -0.40944249465106974, \
         0.18487576156490904, -0.18487576156490904, 0.20720042627424531, \
         -0.20720042627424531]\n\
         [problem]\nperiod = 4.595612975161993\n",
    );
    let v = common::optimize_json(&model, &["--method", "phase", "--phases", "3"]);
    let j = v["objective"].as_f64().unwrap();
    assert!((j - 2.496835698).abs() < 1e-8, "J = {j}");
    let upper = [0.2307750432594322, 4.4535544824622555];
    for u in v["solution"]["controls"].as_array().unwrap() {
        for (l, x) in u.as_array().unwrap().iter().enumerate() {
            let x = x.as_f64().unwrap();
            assert!(x.abs() <= upper[l], "control {l} = {x} outside U");
        }
    }
    common::certify_written(dir.path(), &v);
}

/// A phase polish whose KKT matrix spans many orders of magnitude (a quadratic cost of 1e-6
/// beside controls up to 800): nalgebra's SVD iterated without limit there, and `optimize
/// --method phase --phases 2 --time-limit 5` ran on past 120 s, beyond any deadline. Every
/// decomposition now has a cap on its iterations (`crawlopt::linalg`): the answer comes in
/// well under the limit (0.06 s measured), killed and failed here after 60 s.
#[test]
fn a_badly_scaled_polish_ends_within_the_time_limit() {
    let dir = tempfile::tempdir().unwrap();
    let file = common::write(
        dir.path(),
        "scales.toml",
        "[sweeping_process]\nnormals = [[2.5, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]\n\
         offsets = [1.28, 0.33, 0.87, 0.81]\n[dynamics]\nB = [[-0.56], [-0.37]]\n\
         [control]\nlower = [-400.0]\nupper = [800.0]\nzero_mean = false\n\
         [objective]\nface_weights = [0.98, 0.0, 0.22, 0.41]\n\
         cost = { kind = \"quadratic\", weight = 1e-06 }\n\
         [problem]\nperiod = 10.0\nperiodic = false\ninitial_state = [0.27, -0.027]\n",
    );
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_crawlopt"))
        .args(["optimize", file.to_str().unwrap(), "--method", "phase"])
        .args(["--phases", "2", "--time-limit", "5", "--json"])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed().as_secs() > 60 {
            child.kill().unwrap();
            panic!("still running after 60 s with --time-limit 5");
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    };
    assert!(status.success());
    let mut text = String::new();
    std::io::Read::read_to_string(&mut child.stdout.take().unwrap(), &mut text).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let (j, bound) = (
        v["objective"].as_f64().unwrap(),
        v["certificate"]["bound"].as_f64().unwrap(),
    );
    assert!(j <= bound + 1e-9 && j > 1.0, "J = {j}, bound {bound}");
}

/// Controls of 1000 over a period of 300 in a triangle C of size 1 (and of 1e-4): states are
/// sums of increments of 3e5 and carry their rounding (2e-10 seen), far above a tolerance
/// relative to C alone. The phase gait and P_2's process were written and then refused by
/// `certify` ("reaction on a face not active at both ends of the phase", "reaction on an
/// inactive face"), and at the scale 1e-4 `optimize` refused its own phase gait ("states off
/// by 2.05e-10") and `certify` the P_2 process ("not periodic"). States are now checked to
/// their tolerance relative to C plus 1e3 units in the last place of the largest increment of
/// a piece (`GeneralProblem::rounding`): every answer is given, reads back and certifies; and
/// the phase gait's states moved by 1e-3 of C's scale (off the faces that react) are still
/// refused, naming the states.
#[test]
fn states_are_checked_at_the_scale_of_their_increments() {
    let dir = tempfile::tempdir().unwrap();
    for offsets in ["[1.0, 0.7, 1.2]", "[1.0e-4, 0.7e-4, 1.2e-4]"] {
        let file = common::write(
            dir.path(),
            "wide.toml",
            &format!(
                "[sweeping_process]\nnormals = [[1.0, 0.2], [-0.3, 1.0], [-0.6, -0.9]]\n\
                 offsets = {offsets}\n[dynamics]\nB = [[1.0, 0.0], [0.0, 1.0]]\n\
                 [control]\nlower = [-1000.0, -1000.0]\nupper = [1000.0, 1000.0]\n\
                 zero_mean = false\n[objective]\nface_weights = [0.5, 0.3, 0.4]\n\
                 [problem]\nperiod = 300.0\n"
            ),
        );
        for args in [
            ["--method", "phase", "--phases", "1"],
            ["--method", "discrete", "--m", "2"],
        ] {
            let mut all = vec!["optimize", file.to_str().unwrap()];
            all.extend(args);
            all.push("--json");
            let v = common::crawlopt_json(&all);
            let j = v["objective"].as_f64().unwrap();
            assert!(j > 4.9e5 && j <= v["certificate"]["bound"].as_f64().unwrap() + 1.0);
            common::certify_written(dir.path(), &v);
            if v["method"] == "phase" {
                let mut w = v.clone();
                let scale = if offsets.contains("e-4") { 1.2e-4 } else { 1.2 };
                for x in w["solution"]["states"].as_array_mut().unwrap() {
                    let x0 = x[0].as_f64().unwrap();
                    x[0] = serde_json::json!(x0 - 1e-3 * scale);
                }
                let moved = common::write(dir.path(), "moved.json", &w.to_string());
                let out = common::crawlopt(&["certify", moved.to_str().unwrap()]);
                assert_eq!(out.status.code(), Some(2));
                let err = String::from_utf8_lossy(&out.stderr);
                assert!(err.contains("solution.states["), "{err}");
            }
        }
    }
}

/// One link of half-width `a = 1e-4`, `|u| <= 1`, weights 1/2, zero mean: the best gait crosses
/// C at full rate and pushes on each face for the rest of its half period, `J = T/2 - 2a`. At
/// `T = 1e-3` the phase MILP's reaction rates `L / tau` came out as `1 + 1e-6` where the exact
/// replay's are 1, and `certify` refused the written gait ("int f1 of the stored reactions
/// disagrees with the exact replay's"); at `T = 1e-2` it read back. The stored rates are now
/// the replay's: `J` is the closed form and each result reads back, each phase's step
/// `x_{j+1} = x_j + tau_j (u_j - sum lambda x*)` holding to `1e-8` of C's size (the MILP's
/// durations' tolerance: a crossing `2e-13` longer than C's width takes, seen at `T = 1e-2`;
/// the MILP's rates left `3e-10` at `T = 1e-3`).
#[test]
fn a_phase_gaits_stored_reactions_are_its_replays() {
    let dir = tempfile::tempdir().unwrap();
    let a = 1e-4;
    for t in [1e-2, 1e-3] {
        let file = small_link(dir.path(), a, t);
        let v = phase_answer(&file, "2");
        let j = v["objective"].as_f64().unwrap();
        assert!((j - (t / 2.0 - 2.0 * a)).abs() < 1e-12, "T = {t}: J = {j}");
        let s = &v["solution"];
        let rows = |k: &str| -> Vec<Vec<f64>> { serde_json::from_value(s[k].clone()).unwrap() };
        let (x, u, lam) = (rows("states"), rows("controls"), rows("reactions"));
        for (i, d) in s["durations"].as_array().unwrap().iter().enumerate() {
            let d = d.as_f64().unwrap();
            let step = x[i][0] + d * (u[i][0] - lam[i][0] + lam[i][1]) - x[i + 1][0];
            assert!(
                step.abs() < 1e-8 * a,
                "T = {t}, phase {i}: residual {step:e}"
            );
        }
        common::certify_written(dir.path(), &v);
    }
}

/// The paper's §4 one link as (P): `C = [-a, a]`, `U = [-1, 1]` with zero mean, face weights
/// 1/2 (`J` the displacement), period `t`; written into `dir`.
fn small_link(dir: &std::path::Path, a: f64, t: f64) -> std::path::PathBuf {
    common::write(
        dir,
        "small.toml",
        &format!(
            "[sweeping_process]\nnormals = [[1.0], [-1.0]]\noffsets = [{a:e}, {a:e}]\n\
             [dynamics]\nB = [[1.0]]\n[control]\nlower = [-1.0]\nupper = [1.0]\n\
             zero_mean = true\n[objective]\nface_weights = [0.5, 0.5]\n\
             [problem]\nperiod = {t:e}\n"
        ),
    )
}

/// `optimize FILE --method phase --phases K --json`.
fn phase_answer(file: &std::path::Path, k: &str) -> serde_json::Value {
    common::crawlopt_json(&[
        "optimize",
        file.to_str().unwrap(),
        "--method",
        "phase",
        "--phases",
        k,
        "--json",
    ])
}

/// One link of half-width `a = 1e-4` over periods 5 to 100 times as long (`J = T/2 - 2a`, the
/// paper's §4 optimum). The phase MILP was solved in the problem's own units, where HiGHS's
/// absolute tolerance (`1e-9`) is `1e-5` of C's size: at `T = 5e-4` and `2e-3` the control's
/// mean came out `1e-7` and `4e-7` of its bound and `certify` refused the written answer
/// ("must have zero mean"), at `T = 1e-2`, `K = 4` the replay ended `9.5e-11` from where it
/// began ("not periodic"), and at `T = 5e-4`, `K = 5` `optimize` refused its own MILP's
/// `int f1` (`1e-6` above the replay's). In units of order one (C's size, U's bound, the time
/// to cross C) every answer is the closed form to `1e-9` and reads back.
#[test]
fn short_periods_on_a_small_link_give_the_closed_form_and_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let a = 1e-4;
    for t in [5e-4, 2e-3, 1e-2] {
        let file = small_link(dir.path(), a, t);
        for k in ["2", "3", "4", "5"] {
            let v = phase_answer(&file, k);
            let j = v["objective"].as_f64().unwrap();
            let want = t / 2.0 - 2.0 * a;
            assert!(
                (j - want).abs() <= 1e-9 * want,
                "T = {t}, K = {k}: J = {j}, not {want}"
            );
            common::certify_written(dir.path(), &v);
        }
    }
}

/// P_m of one link of half-width `a` over `T = 20 a` to `100 a`, against the same link in units
/// where `a = 1` (`J` scales by `a`; here the grid reaches `T/2 - 2a`). The MILP was solved in
/// the problem's own units, where HiGHS's absolute tolerance is up to `3e-4` of C's size: at
/// `a = 1e-5`, `T = 1e-3`, `m = 4` it claimed a global optimum with a bound `1.3e-7` of `J`
/// below the twin's optimum; at `a = 3e-6`, `T = 6e-5`, `m = 4` `optimize` failed ("the
/// simulated process is not periodic"); at `a = 1e-5`, `T = 6e-4`, `m = 5` it claimed a global
/// optimum `2.8e-7` of `J` below the twin's, its bound equal. (At `a = 1e-4`, `T = 2e-3`,
/// `m = 6`, too slow for a test, it claimed `J = 7.6876e-4` against `8e-4`.) In units of order
/// one each gives the twin's optimum, and reads back.
#[test]
fn p_m_on_a_small_link_is_the_optimum_of_the_link_in_units_of_one() {
    let dir = tempfile::tempdir().unwrap();
    for (a, t, m) in [(1e-5, 1e-3, "4"), (3e-6, 6e-5, "4"), (1e-5, 6e-4, "5")] {
        let run = |a: f64, t: f64| {
            let file = small_link(dir.path(), a, t);
            let args = ["optimize", file.to_str().unwrap(), "--method", "discrete"];
            let v = common::crawlopt_json(&[&args[..], &["--m", m, "--json"]].concat());
            common::certify_written(dir.path(), &v);
            let j = v["objective"].as_f64().unwrap();
            (j / a, v["certificate"]["bound"].as_f64().unwrap() / a)
        };
        let (j, bound) = run(a, t);
        let (twin, _) = run(1.0, t / a);
        let want = t / a / 2.0 - 2.0;
        assert!((twin - want).abs() <= 1e-9 * want, "the twin: J = {twin}");
        assert!(
            (j - twin).abs() <= 1e-9 * want && bound >= twin - 1e-9 * want,
            "a = {a}, T = {t}, m = {m}: J / a = {j}, bound / a = {bound}, not {twin}"
        );
    }
}

/// The square C of half-width `a` with U the unit square turned by 45 degrees (a polytope), in
/// time `s` times slower: `B = (a / s) I`, `T = 10 s` (an exact twin of `a = s = 1`).
fn polytope_u(a: f64, s: f64) -> String {
    format!(
        "[sweeping_process]\nnormals = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]]\n\
         offsets = [{a:?}, {a:?}, {a:?}, {a:?}]\n[dynamics]\nB = [[{b:?}, 0.0], [0.0, {b:?}]]\n\
         [control]\nG = [[1.0, 1.0], [-1.0, 1.0], [1.0, -1.0], [-1.0, -1.0]]\n\
         h = [1.0, 1.0, 1.0, 1.0]\nzero_mean = true\n\
         [objective]\nface_weights = [1.0, 0.0, 0.3, 0.0]\n[problem]\nperiod = {t:?}\n",
        b = a / s,
        t = 10.0 * s
    )
}

/// A triangle C of scale `a` with a box U and a coupled `B`, in time `s` times slower.
fn box_u(a: f64, s: f64) -> String {
    format!(
        "[sweeping_process]\nnormals = [[1.0, 0.0], [0.0, 1.0], [-1.0, -1.0]]\n\
         offsets = [{a:?}, {a:?}, {a:?}]\n[dynamics]\nB = [[{b:?}, {c:?}], [{d:?}, {b:?}]]\n\
         [control]\nlower = [-1.0, -1.0]\nupper = [1.0, 1.0]\nzero_mean = true\n\
         [objective]\nface_weights = [0.5, 0.3, 0.4]\n[problem]\nperiod = {t:?}\n",
        b = a / s,
        c = 0.3 * a / s,
        d = 0.2 * a / s,
        t = 10.0 * s
    )
}

/// Exact twins (one problem in other units: states times `a`, time times `s`) have one
/// optimum, claimed as such and read back: P_3 and the phase MILP of a polytope U in slow time
/// (`B` of size `1e-8`: the support LP of U took every vertex for optimal, bounded the
/// multipliers by 0, and both MILPs claimed `J = 0` or `3.9e-4` optimal where `J = 3.9`), and
/// P_3 and P_4 of a box U at C's scale `0.01` and `0.02` (solved in the problem's own units,
/// P_3 was claimed optimal at `J / a = 3.653` and `4.097` where the grid reaches `6.487`).
#[test]
fn exact_twins_have_one_optimum() {
    let dir = tempfile::tempdir().unwrap();
    /// A family of twins, the twins `(a, s)` checked, and the methods' arguments.
    type Case<'a> = (
        fn(f64, f64) -> String,
        &'a [(f64, f64)],
        &'a [&'a [&'a str]],
    );
    let cases: [Case; 2] = [
        (
            polytope_u,
            &[(1e-4, 1e4), (1.0, 1e8)],
            &[
                &["--method", "discrete", "--m", "3"],
                &["--method", "phase"],
            ],
        ),
        (
            box_u,
            &[(0.01, 1.0), (0.02, 1.0)],
            &[&["--m", "3"], &["--m", "4"]],
        ),
    ];
    for (make, twins, methods) in cases {
        for args in methods {
            let run = |a: f64, s: f64| {
                let file = common::write(dir.path(), "twin.toml", &make(a, s));
                let v = common::optimize_json(&file, args);
                common::certify_written(dir.path(), &v);
                let bound = v["certificate"]["bound"].as_f64().unwrap();
                (v["objective"].as_f64().unwrap() / a, bound / a)
            };
            let (want, _) = run(1.0, 1.0);
            assert!(want > 1.0, "{args:?}: J = {want}");
            for &(a, s) in twins {
                let (j, bound) = run(a, s);
                assert!(
                    (j - want).abs() <= 1e-9 * want && bound >= want - 1e-9 * want,
                    "{args:?}, a = {a}, s = {s}: J / a = {j}, bound / a = {bound}, not {want}"
                );
            }
        }
    }
}

/// The three-block crawler as (P) at C's scale `a` (`B = a I`, offsets `a` times), and the
/// drift example's square at scale `a` with its cost times `a`: exact twins of `a = 1`.
fn chain_twin(a: f64) -> String {
    let text = include_str!("../examples/general_three_blocks.toml");
    let offsets = [1.0, 1.5, 1.0, 1.5, 1.0, 1.5].map(|v| format!("{:?}", v * a));
    text.replace(
        "offsets = [1.0, 1.5, 1.0, 1.5, 1.0, 1.5]",
        &format!("offsets = [{}]", offsets.join(", ")),
    )
    .replace(
        "B = [[1.0, 0.0], [0.0, 1.0]]",
        &format!("B = [[{a:?}, 0.0], [0.0, {a:?}]]"),
    )
}

/// (See [`chain_twin`].)
fn drift_twin(a: f64) -> String {
    let text = include_str!("../examples/general_drift.toml");
    text.replace(
        "offsets = [1.0, 1.0, 1.0, 1.0]",
        &format!("offsets = [{a:?}, {a:?}, {a:?}, {a:?}]"),
    )
    .replace(
        "B = [[1.0, 0.0], [0.0, 1.0]]",
        &format!("B = [[{a:?}, 0.0], [0.0, {a:?}]]"),
    )
    .replace("weight = 0.1", &format!("weight = {:?}", 0.1 * a))
}

/// Ties and gaps relative to the problem's floor of `J` (C's scale capped at 1), not to 1:
/// the chain at C's scale `1e-6` with `K = 2` keeps the start its twin keeps (every structured
/// gait tied at an absolute `1e-12`, and the lag 3/16, `J / a = 1.375`, was kept where the twin
/// keeps the lag 4/16, `1.5`), and the drift's P_3 at `1e-6`, which stops `3.6e-7` of `J`
/// below its twin's optimum (within the outer approximation's `1e-6`), states that gap (it
/// stated `4.8e-13`, absolute).
#[test]
fn exact_twins_of_small_scale_keep_the_start_and_state_the_gap() {
    let dir = tempfile::tempdir().unwrap();
    let run = |text: String, args: &[&str], a: f64| {
        let file = common::write(dir.path(), "twin.toml", &text);
        let v = common::optimize_json(&file, args);
        common::certify_written(dir.path(), &v);
        (v["objective"].as_f64().unwrap() / a, v)
    };
    let phases = ["--method", "phase", "--phases", "2"];
    let (want, _) = run(chain_twin(1.0), &phases, 1.0);
    assert!((want - 1.5).abs() < 1e-9, "{want}");
    let (j, v) = run(chain_twin(1e-6), &phases, 1e-6);
    assert!((j - want).abs() <= 1e-9 * want, "J / a = {j}, not {want}");
    assert_eq!(v["status"], "dominates_k_phases");
    let p3 = ["--method", "discrete", "--m", "3"];
    let (want, _) = run(drift_twin(1.0), &p3, 1.0);
    let (j, v) = run(drift_twin(1e-6), &p3, 1e-6);
    let gap = v["certificate"]["gap"].as_f64().unwrap();
    let short = (want - j) / want;
    assert!(
        short <= 1.01 * gap + 1e-12,
        "J / a = {j} is {short:e} below the twin's {want}, the gap stated is {gap:e}"
    );
}

/// A long C whose far face is 1e13 away (the one link's C = [-1e13, 1]): the bang-bang input
/// moves x by 10 a period and never reaches the far face, so the periodic orbit runs from -4 up
/// to the face x <= 1 and back, and J = 0 (the closed form `max(0, (T - 2 (b - a)) / 2)`).
/// Both simulators and the phase method (its J verified by the exact simulator) must say so:
/// tolerances of `1e-12` and `1e-14` of C's scale (10 and 0.1 here) held the near face as
/// active 6 away, or kept the projection on it, and reported J = 2.5 with exit 0; the crawler
/// with the same thresholds (`mu- = 1e13`) gave 0. At 1e300 too.
#[test]
fn a_far_face_does_not_blur_the_near_one() {
    for far in ["1e13", "1e300"] {
        let text = ONE_LINK.replace("offsets = [1.0, 1.0]", &format!("offsets = [1.0, {far}]"));
        for method in [GeneralMethod::Auto, GeneralMethod::CatchingUp] {
            let o = GeneralSimOptions {
                method,
                ..steps(1000)
            };
            let s = api::simulate_general(&file(&text), &o).unwrap().simulation;
            assert!(
                s.objective.unwrap().abs() < 1e-9,
                "{far}, {method:?}: {:?}",
                s.objective
            );
            assert!(
                (s.x[0][0] + 4.0).abs() < 1e-6,
                "{far}, {method:?}: x(0) = {:?}",
                s.x[0]
            );
        }
    }
    let text = ONE_LINK.replace("offsets = [1.0, 1.0]", "offsets = [1.0, 1e13]");
    let s = api::GeneralPhaseSettings::default();
    let r = api::optimize_general_phase(&file(&text), &s, api::Hooks::default()).unwrap();
    assert!(
        r.head.objective.abs() < 1e-9,
        "phase: J = {}",
        r.head.objective
    );
}
