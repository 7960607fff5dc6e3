//! The necessary conditions on exact phase gaits of the general problem (`A = 0`; theory §7
//! generalised, `crawlopt::certify::general`): the branch LP of a phase gait has its durations
//! as variables too, so besides the conditions with the durations fixed the maximised
//! Hamiltonian must be the same on every phase. The §4 one-link optimum holds; a gait that is
//! optimal for its durations but not in them fails on that condition alone; processes that are
//! not phase gaits are refused naming the field; `optimize --method phase --certify` and
//! `certify` of its result give the same certificate. (Crawler phase optima against the
//! crawler's certificate: tests/general_certify.rs.)

mod common;

use common::crawlopt;
use crawlopt::api::{general_problem, optimize_general_phase, GeneralPhaseSettings, Hooks};
use crawlopt::certify::{certify_general, CertifyOptions, GeneralProcess, ProcessKind, Verdict};
use crawlopt::io::GeneralFile;
use crawlopt::model::general::GeneralProblem;

fn one_link() -> (GeneralFile, GeneralProblem) {
    let text = std::fs::read_to_string("examples/general_one_link.toml").unwrap();
    let file = GeneralFile::parse(&text).unwrap();
    let (p, _) = general_problem(&file).unwrap();
    (file, p)
}

fn residual(c: &crawlopt::certify::GeneralNecessaryConditions, name: &str) -> f64 {
    c.conditions
        .iter()
        .find(|k| k.name == name && k.theorem == "6.2")
        .unwrap_or_else(|| panic!("no condition {name}"))
        .residual
}

/// The one-link gait at half rate on its rises and falls: `u = 1/2` for 4 (from `x = -1` to
/// `1`), `u = 1` for 1 on the upper face (reaction 1), `u = -1/2` for 4, `u = -1` for 1 on the
/// lower face. `J = 1/2 (1 + 1) = 1`.
fn slow_gait() -> GeneralProcess {
    GeneralProcess {
        kind: ProcessKind::Phase,
        durations: vec![4.0, 1.0, 4.0, 1.0],
        x: vec![vec![-1.0], vec![1.0], vec![1.0], vec![-1.0], vec![-1.0]],
        u: vec![vec![0.5], vec![1.0], vec![-0.5], vec![-1.0]],
        lambda: vec![
            vec![0.0, 0.0],
            vec![1.0, 0.0],
            vec![0.0, 0.0],
            vec![0.0, 1.0],
        ],
    }
}

/// §4: the phase optimum (J = 3: free rise, slide on the upper face, free fall, slide on the
/// lower one) satisfies every condition, the duration stationarity included, with lambda = 1
/// and `p = -1/2` on the rise and its slide, `+1/2` on the fall and its slide (`p` jumps by the
/// `dxi` mass 1 where a slide ends), as the crawler's phase certificate has it.
#[test]
fn the_one_link_phase_optimum_holds() {
    let (file, p) = one_link();
    let s = GeneralPhaseSettings {
        certify: true,
        ..Default::default()
    };
    let r = optimize_general_phase(&file, &s, Hooks::default()).unwrap();
    assert!(
        (r.head.objective - 3.0).abs() < 1e-9,
        "{}",
        r.head.objective
    );
    let c = r.necessary_conditions.as_ref().unwrap();
    assert_eq!(c.verdict, Verdict::Holds, "{}", c.reason);
    assert_eq!((c.method.as_str(), c.m, c.lambda), ("phase", None, 1.0));
    for k in &c.conditions {
        assert!(k.holds && k.residual <= 1e-9, "{} {}", k.name, k.residual);
    }
    assert!(residual(c, "duration_stationarity") <= 1e-9);
    let switching = &c.multipliers.switching;
    let g = r.solution.as_phase().unwrap();
    for (u, s) in g.controls.iter().zip(switching) {
        assert!(
            (s[0].abs() - 0.5).abs() < 1e-9 && s[0] * u[0] < 0.0,
            "{s:?} {u:?}"
        );
    }
    assert!(c
        .multipliers
        .xi
        .iter()
        .all(|x| (x.value - 1.0).abs() < 1e-9));
    // The times of the multipliers are the gait's knots.
    let mut t = vec![0.0];
    for d in &g.durations {
        t.push(t[t.len() - 1] + d);
    }
    assert_eq!(c.multipliers.times, t);
    // Certified afresh from the process: the same certificate.
    let again = certify_general(
        &p,
        &GeneralProcess::from_phase(g),
        &CertifyOptions::default(),
    )
    .unwrap();
    assert_eq!(&again, c);
}

/// The slow gait is optimal for its durations (the rises must cover C, the slides are at full
/// rate; the rises' interior control asks `B^T p + omega = 0` there, which multipliers meet), so
/// every discrete condition with the durations fixed holds; but shortening a rise to 2 and
/// lengthening a slide gains (J = 3 is the optimum): the phase LP is not stationary in the
/// durations, and the multipliers with the durations fixed need `dxi < 0` (Theorem 2.2's sign,
/// required of an exact gait as of the crawler's; the rises' `B^T p + omega = 0` is degenerate too).
/// The verdict is `fails`.
#[test]
fn a_gait_optimal_only_for_its_durations_fails_on_them() {
    let (_, p) = one_link();
    let pr = slow_gait();
    let c = certify_general(&p, &pr, &CertifyOptions::default()).unwrap();
    assert!((c.objective - 1.0).abs() < 1e-12, "{}", c.objective);
    assert_eq!(c.verdict, Verdict::Fails, "{}", c.reason);
    assert!(residual(&c, "duration_stationarity") > 1e-3);
    let failing = |th: &str| -> Vec<&str> {
        c.conditions
            .iter()
            .filter(|k| k.theorem == th && !k.holds)
            .map(|k| k.name.as_str())
            .collect()
    };
    assert_eq!(failing("6.2"), ["duration_stationarity"], "{}", c.reason);
    assert_eq!(failing("2.2"), ["sign", "nondegeneracy"], "{}", c.reason);
}

/// Processes that are not phase gaits of the problem are refused, naming the field: durations
/// that do not sum to the period, a piece that does not follow from its start, a reaction on a
/// face the segment leaves, a control outside U, controls without zero mean; and a phase gait of
/// a problem with `A != 0` (naming `dynamics.A`).
#[test]
fn inconsistent_phase_gaits_are_refused() {
    let (_, p) = one_link();
    type Edit = Box<dyn Fn(&mut GeneralProcess)>;
    let cases: Vec<(Edit, &str)> = vec![
        (Box::new(|q| q.durations[0] = 3.0), "process.durations"),
        (Box::new(|q| q.durations[1] = 0.0), "process.durations"),
        (Box::new(|q| q.x[1][0] = 0.5), "process.x[1]"),
        (Box::new(|q| q.u[1][0] = 1.5), "process.u[1]"),
        (
            Box::new(|q| {
                // The rise pushed by the lower face (active at its start only) at rate 1/4, the
                // fall by the upper one: the dynamics and the mean still hold.
                q.u[0][0] = 0.25;
                q.lambda[0][1] = 0.25;
                q.u[2][0] = -0.25;
                q.lambda[2][0] = 0.25;
            }),
            "process.lambda[0][1]",
        ),
        (
            Box::new(|q| {
                q.u[1][0] = 0.5;
                q.lambda[1][0] = 0.5;
            }),
            "process.u",
        ),
    ];
    for (edit, field) in cases {
        let mut q = slow_gait();
        edit(&mut q);
        let e = certify_general(&p, &q, &CertifyOptions::default())
            .unwrap_err()
            .to_string();
        assert!(e.starts_with(field), "{field}: {e}");
    }
    let text = std::fs::read_to_string("examples/general_one_link.toml")
        .unwrap()
        .replace("B = [[1.0]]", "A = [[-0.1]]\nB = [[1.0]]");
    let (drift, _) = general_problem(&GeneralFile::parse(&text).unwrap()).unwrap();
    let e = certify_general(&drift, &slow_gait(), &CertifyOptions::default()).unwrap_err();
    assert!(e.to_string().starts_with("dynamics.A"), "{e}");
}

/// `crawlopt optimize GENERAL.toml --method phase --certify`: the certificate in the text and,
/// with `--json`, as `necessary_conditions`; `crawlopt certify` of that result gives the same
/// verdict (the three-block crawler in general form: `degenerate`, as the crawler's own
/// certificate of its phase optimum).
#[test]
fn optimize_phase_certify_and_certify_agree() {
    for (file, verdict) in [
        ("examples/general_one_link.toml", "holds"),
        ("examples/general_three_blocks.toml", "degenerate"),
    ] {
        let args = ["optimize", file, "--method", "phase", "--certify"];
        let out = crawlopt(&args);
        let text = String::from_utf8_lossy(&out.stdout);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            text.contains(&format!(
                "necessary conditions (Theorem 2.2; discrete form Theorems 6.1-6.2): {verdict}"
            )),
            "{text}"
        );
        assert!(text.contains("duration_stationarity"), "{text}");
        let mut json = args.to_vec();
        json.push("--json");
        let out = crawlopt(&json);
        assert!(out.status.success());
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let c = &v["necessary_conditions"];
        assert_eq!(
            (c["verdict"].as_str(), c["method"].as_str()),
            (Some(verdict), Some("phase"))
        );
        assert!(c["m"].is_null());
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("r.json");
        std::fs::write(&f, &out.stdout).unwrap();
        let out = crawlopt(&["certify", f.to_str().unwrap(), "--json"]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let back: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(&back, c, "{file}");
    }
}

/// A phase of the solver's resolution (here `1e-10 T` with an interior control, as the MILP can
/// leave one) is dropped before certifying: its duration is 0 for the phase LP, at the bound
/// `tau >= 0`, where neither its control's maximality nor its Hamiltonian is asked. The §4
/// optimum with such a phase after its rise holds, on its four phases.
#[test]
fn an_empty_phase_is_dropped() {
    let (_, p) = one_link();
    let tiny = 1e-9;
    let pr = GeneralProcess {
        kind: ProcessKind::Phase,
        durations: vec![2.0, tiny, 3.0, 2.0, 3.0],
        x: vec![
            vec![-1.0],
            vec![1.0],
            vec![1.0 - 0.3 * tiny],
            vec![1.0],
            vec![-1.0],
            vec![-1.0],
        ],
        u: vec![vec![1.0], vec![-0.3], vec![1.0], vec![-1.0], vec![-1.0]],
        lambda: vec![
            vec![0.0, 0.0],
            vec![0.0, 0.0],
            vec![1.0, 0.0],
            vec![0.0, 0.0],
            vec![0.0, 1.0],
        ],
    };
    let c = certify_general(&p, &pr, &CertifyOptions::default()).unwrap();
    assert_eq!(c.verdict, Verdict::Holds, "{}", c.reason);
    assert!((c.objective - 3.0).abs() < 1e-9, "{}", c.objective);
    assert_eq!(c.multipliers.times, [0.0, 2.0, 5.0, 7.0, 10.0]);
    assert_eq!(
        pr.without_empty_phases(p.period).durations,
        [2.0, 3.0, 2.0, 3.0]
    );
}

/// The duration condition's rows substitute an axis row's weight `psi_l / v`, which brings in
/// `p_i` through `B`, and the drift `b` brings `p_i` in again: two controls at a bound with a
/// non-diagonal `B`, or one with `b != 0`, put a column twice in one row, which HiGHS refused
/// (exit 2 on a gait it had just found). Both now certify, with the verdicts the crawler-free
/// formulation (a column per normal-cone weight) gave: the 3-phase gaits `degenerate`, the
/// 4-phase ones `fails` on Theorem 2.2's sign (0.5), the duration condition holding. These are
/// the general formulation's gaits (`--formulation general`): with free transitions, the default
/// here, K = 2 slots already reach the 4-phase gait (J = 6, the same verdict) and K = 3 gives a
/// 5-phase gait of the same J.
#[test]
fn phase_gaits_with_a_coupling_b_or_a_drift_certify() {
    let square =
        "[sweeping_process]\nnormals = [[1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0]]\n\
                  offsets = [1.0, 1.0, 1.0, 1.0]\n[control]\nlower = [-1.0, -1.0]\n\
                  upper = [1.0, 1.0]\nzero_mean = true\n[problem]\nperiod = 10.0\n";
    let coupled = format!(
        "{square}[dynamics]\nB = [[1.0, 0.4], [0.0, 1.0]]\n[objective]\nface_weights = [1.0, 0.6, 0.0, 0.0]\n"
    );
    let drifting = format!(
        "{square}[dynamics]\nB = [[1.0, 0.0], [0.0, 1.0]]\nb = [0.2, -0.1]\n[objective]\nface_weights = [1.0, 0.5, 0.0, 0.0]\n"
    );
    let dir = tempfile::tempdir().unwrap();
    for (name, text) in [("coupled", coupled), ("drifting", drifting)] {
        let f = dir.path().join(format!("{name}.toml"));
        std::fs::write(&f, text).unwrap();
        for (k, verdict) in [("3", "degenerate"), ("4", "fails")] {
            let args = [
                "optimize",
                f.to_str().unwrap(),
                "--method",
                "phase",
                "--phases",
                k,
                "--formulation",
                "general",
                "--certify",
                "--json",
            ];
            let out = crawlopt(&args);
            assert!(
                out.status.success(),
                "{name} K = {k}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
            let c = &v["necessary_conditions"];
            assert_eq!(c["verdict"].as_str(), Some(verdict), "{name} K = {k}");
            let duration = c["conditions"]
                .as_array()
                .unwrap()
                .iter()
                .find(|x| x["name"] == "duration_stationarity")
                .unwrap_or_else(|| panic!("{name} K = {k}: no duration condition"));
            assert!(
                duration["residual"].as_f64().unwrap() <= 1e-9,
                "{name} K = {k}: {duration}"
            );
        }
    }
}

/// The one-link problem in other units: states times `a`, time times `s`, controls times `su`
/// (an exact twin of `a = s = su = 1`).
fn one_link_twin(a: f64, s: f64, su: f64) -> String {
    let text = std::fs::read_to_string("examples/general_one_link.toml").unwrap();
    let text = &text[..text.rfind("[input]").unwrap()];
    text.replace("offsets = [1.0, 1.0]", &format!("offsets = [{a:?}, {a:?}]"))
        .replace("B = [[1.0]]", &format!("B = [[{:?}]]", a / s / su))
        .replace("period = 10.0", &format!("period = {:?}", 10.0 * s))
        .replace("lower = [-1.0]", &format!("lower = [{:?}]", -su))
        .replace("upper = [1.0]", &format!("upper = [{su:?}]"))
}

/// A verdict does not depend on units: the one-link optimum of the phase method and of P_3
/// `holds` in every twin, each residual in units that scale with it, and the non-degeneracy
/// margin (in units of the switching function, `B^T p`) is the twin's times `a / (s su)`. With
/// absolute residuals the phase optimum `failed` at `a = 1e5` (complementarity and duration
/// stationarity `1.3e-9`, rounding of slacks of size `1e5`) and P_3 was `degenerate` wherever
/// `B` is `1e-6` (states of `1e-6`, time `1e6` times slower, controls `1e6` times larger): its
/// margin `5e-7` was held to the unit `max |w| = 0.5` of a problem in units of one.
#[test]
fn a_verdict_is_the_same_in_any_units() {
    let dir = tempfile::tempdir().unwrap();
    for method in [
        &["--method", "phase"][..],
        &["--method", "discrete", "--m", "3"],
    ] {
        let run = |a: f64, s: f64, su: f64| {
            let file = common::write(dir.path(), "twin.toml", &one_link_twin(a, s, su));
            let c = common::certify_written(dir.path(), &common::optimize_json(&file, method));
            let margin = c["nondegeneracy_margin"].as_f64().unwrap();
            (
                c["verdict"].as_str().unwrap().to_string(),
                margin / (a / s / su),
            )
        };
        let (verdict, margin) = run(1.0, 1.0, 1.0);
        assert!(
            verdict == "holds" && (margin - 0.5).abs() < 1e-9,
            "{method:?}: {verdict}, margin {margin}"
        );
        for (a, s, su) in [
            (1e5, 1.0, 1.0),
            (1e-6, 1.0, 1.0),
            (1.0, 1e6, 1.0),
            (1.0, 1.0, 1e6),
        ] {
            let (v, m) = run(a, s, su);
            assert!(
                v == verdict && (m - margin).abs() <= 1e-6 * margin,
                "{method:?}, a = {a}, s = {s}, su = {su}: {v}, margin {m} in the twin's units"
            );
        }
    }
    // The multiplier LPs bound each violation in the residual's unit too: the three-block
    // local optimum with controls a million times larger (`B = 1e-6 I`) `failed` (weak
    // maximality `1e-6`: the LPs' absolute slack of `1e-12` on `psi`, counted in units of
    // `1e-6`), where at scale 1 it is `degenerate`.
    let text = std::fs::read_to_string("examples/general_three_blocks.toml").unwrap();
    let verdict = |text: &str| {
        let file = common::write(dir.path(), "twin.toml", text);
        let v = common::optimize_json(&file, &["--method", "local"]);
        let c = common::certify_written(dir.path(), &v);
        c["verdict"].as_str().unwrap().to_string()
    };
    let twin = text
        .replace(
            "B = [[1.0, 0.0], [0.0, 1.0]]",
            "B = [[1e-6, 0.0], [0.0, 1e-6]]",
        )
        .replace("lower = [-1.0, -1.0]", "lower = [-1e6, -1e6]")
        .replace("upper = [1.0, 1.0]", "upper = [1e6, 1e6]");
    assert_eq!(verdict(&twin), verdict(&text));
}
