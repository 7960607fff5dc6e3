//! A general problem (P) that is a long crawler's chain (11 blocks and more: beyond C's vertex
//! enumeration, which tries `C(2N, N - 1)` subsets of faces): its face weights are decided by
//! the chain's uniqueness condition (paper eq. 3.6) and the MILPs' multiplier bound by the
//! chain's structure, so every command runs on it; the numbers are the crawler's closed forms.

mod common;

use common::{crawlopt, write};
use crawlopt::api::{analyze_general, simulate_general};
use crawlopt::integrate::{simulate_general_exact, GeneralMethod, GeneralSimOptions};
use crawlopt::io::{CheckStatus, GeneralFile};
use crawlopt::model::general::GeneralProblem;
use crawlopt::optimal::general::analyze_polyhedron;

/// A chain of `blocks` blocks with per-link stiffness `k`, per-block thresholds `mu+`, `mu-`
/// (unit normals `+-K^(1/2) nu_b / s_b`, weights `+-1 / (N s_b)`), `|u| <= 1` with zero mean,
/// `T = 10`, playing the alternating square wave of the rates (odd links against even links,
/// `+-1` on quarters: the alternating triangle wave of the lengths `L' = u / k`).
fn chain_text(k: &[f64], mu_plus: &[f64], mu_minus: &[f64]) -> String {
    let (blocks, n) = (mu_plus.len(), k.len());
    let (mut normals, mut offsets, mut weights) = (Vec::new(), Vec::new(), Vec::new());
    for b in 0..blocks {
        let mut v = vec![0.0; n];
        if b > 0 {
            v[b - 1] = k[b - 1].sqrt();
        }
        if b < n {
            v[b] = -k[b].sqrt();
        }
        let s = v.iter().map(|x: &f64| x * x).sum::<f64>().sqrt();
        let unit: Vec<f64> = v.iter().map(|x| x / s).collect();
        normals.push(format!("{unit:?}"));
        normals.push(format!("{:?}", unit.iter().map(|x| -x).collect::<Vec<_>>()));
        offsets.extend([mu_plus[b] / s, mu_minus[b] / s]);
        weights.extend([1.0 / (blocks as f64 * s), -1.0 / (blocks as f64 * s)]);
    }
    let b: Vec<String> = (0..n)
        .map(|l| {
            let row: Vec<f64> = (0..n)
                .map(|j| if j == l { 1.0 / k[l].sqrt() } else { 0.0 })
                .collect();
            format!("{row:?}")
        })
        .collect();
    let sign = |l: usize| if l % 2 == 0 { 1.0 } else { -1.0 };
    let values: Vec<String> = [1.0, -1.0, -1.0, 1.0]
        .iter()
        .map(|s| format!("{:?}", (0..n).map(|l| s * sign(l)).collect::<Vec<f64>>()))
        .collect();
    format!(
        "[sweeping_process]\nnormals = [{}]\noffsets = {offsets:?}\n\n[dynamics]\nB = [{}]\n\n\
         [control]\nlower = {:?}\nupper = {:?}\nzero_mean = true\n\n[objective]\n\
         face_weights = {weights:?}\n\n[problem]\nperiod = 10.0\n\n[input]\n\
         kind = \"piecewise_constant\"\ntimes = [0.0, 2.5, 5.0, 7.5]\nvalues = [{}]\n",
        normals.join(", "),
        b.join(", "),
        vec![-1.0; n],
        vec![1.0; n],
        values.join(", ")
    )
}

fn uniform(blocks: usize, mu_minus: f64) -> GeneralFile {
    GeneralFile::parse(&uniform_text(blocks, mu_minus)).unwrap()
}

fn uniform_text(blocks: usize, mu_minus: f64) -> String {
    chain_text(
        &vec![1.0; blocks - 1],
        &vec![1.0; blocks],
        &vec![mu_minus; blocks],
    )
}

/// Twenty blocks: well posed by the chain's own check (C's vertices are not enumerated), and
/// the alternating triangle wave moves it by the closed form `4 - 1/(N - 1)` (the crawler's,
/// `tests/chains.rs`).
#[test]
fn a_twenty_block_chain_is_accepted_and_moves_by_the_closed_form() {
    let file = uniform(20, 1.3);
    let a = analyze_general(&file).unwrap();
    assert!(a.failure.is_none(), "{:?}", a.failure);
    assert!(a.geometry.vertices.is_none());
    let check = a
        .checks
        .iter()
        .find(|c| c.name == "face weights well defined")
        .unwrap();
    assert_eq!(check.status, CheckStatus::Pass, "{}", check.detail);
    assert!(
        check.detail.contains("a chain of 20 blocks"),
        "{}",
        check.detail
    );
    let s = simulate_general(&file, &GeneralSimOptions::DEFAULT).unwrap();
    let j = s.objective.unwrap();
    assert!((j - (4.0 - 1.0 / 19.0)).abs() < 1e-9, "J = {j}");
}

/// With `mu+ = mu- = 1` and an even number of blocks, half of them forward and half backward
/// balance (paper eq. 3.6 fails): every block can be at a threshold at once, the active
/// normals are dependent there, and the face weights are refused naming the field, by the
/// library and by the CLI (exit 2), at any length.
#[test]
fn a_chain_whose_thresholds_balance_is_refused_naming_the_weights() {
    for blocks in [4, 14] {
        let file = uniform(blocks, 1.0);
        let e = simulate_general(&file, &GeneralSimOptions::DEFAULT).unwrap_err();
        let text = e.to_string();
        assert!(text.contains("objective.face_weights"), "{text}");
        assert!(text.contains("not well defined"), "{text}");
    }
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "balanced.toml",
        &chain_text(&[1.0; 13], &[1.0; 14], &[1.0; 14]),
    );
    let out = crawlopt(&["simulate", path.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("objective.face_weights"), "{err}");
    assert!(
        err.contains("every block can be at a threshold at once"),
        "{err}"
    );
    let a = analyze_general(&uniform(14, 1.0)).unwrap();
    let check = a
        .checks
        .iter()
        .find(|c| c.name == "face weights well defined")
        .unwrap();
    assert_eq!(check.status, CheckStatus::Fail, "{}", check.detail);
}

/// The multiplier bound the chain's structure gives is a lower bound of the least singular
/// value of the active normals over C's vertices (what the MILPs' big-M divides by), checked
/// against the enumeration where it runs (3 to 6 blocks, uneven stiffness and thresholds),
/// which it equals.
#[test]
fn the_chains_singular_value_bound_is_below_every_vertex() {
    for blocks in 3..=6 {
        let k: Vec<f64> = (0..blocks - 1)
            .map(|l| 1.0 + 0.5 * (1.7 * l as f64).sin())
            .collect();
        let mp: Vec<f64> = (0..blocks).map(|b| 1.0 + 0.1 * b as f64).collect();
        let mm: Vec<f64> = (0..blocks).map(|b| 1.37 + 0.05 * b as f64).collect();
        let file = GeneralFile::parse(&chain_text(&k, &mp, &mm)).unwrap();
        let (p, _) = crawlopt::api::general_problem(&file).unwrap();
        let view = p.as_chain().expect("a chain");
        let g = analyze_polyhedron(&p.c).unwrap();
        let vertices = g.vertices.unwrap();
        let enumerated = vertices
            .iter()
            .map(|v| {
                let a = nalgebra::DMatrix::from_fn(v.active.len(), p.c.dim(), |i, j| {
                    p.c.normals[v.active[i] - 1][j]
                });
                a.singular_values().min()
            })
            .fold(f64::INFINITY, f64::min);
        let chain = view.least_active_singular_value(&p.c);
        // A lower bound, and here the value itself: some vertex has N - 1 blocks held.
        assert!(
            (chain - enumerated).abs() <= 1e-9 * enumerated,
            "N = {blocks}: {chain} vs {enumerated}"
        );
        println!("N = {blocks}: chain {chain:.6}, vertices {enumerated:.6}");
    }
}

/// Twelve blocks: the methods that need C's vertices without the chain (P_m's big-M) and
/// those that run the crawler's job all answer; P_1's global optimum is the alternating wave's
/// `4 - 1/11`, the local method from the file's input keeps it, and the chain method says that
/// its answer is that structured gait (the crawler job's record, passed on).
#[test]
fn the_methods_run_on_a_twelve_block_chain() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "chain12.toml",
        &chain_text(&[1.0; 11], &[1.0; 12], &[1.3; 12]),
    );
    let path = path.to_str().unwrap();
    let want = 4.0 - 1.0 / 11.0;
    for args in [
        vec!["--method", "discrete", "--m", "1"],
        vec!["--method", "local", "--m", "3"],
        vec!["--method", "chain", "--time-limit", "5"],
    ] {
        let mut all = vec!["optimize", path, "--json"];
        all.extend(&args);
        let out = crawlopt(&all);
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let j = v["objective"].as_f64().unwrap();
        assert!(j >= want - 1e-9, "{args:?}: J = {j}");
        if args[1] == "discrete" {
            assert!((j - want).abs() < 1e-9, "P_1: J = {j}");
            assert_eq!(v["status"], "optimal");
        }
        if args[1] == "chain" {
            // The crawler job's record passes on: its start, the alternating wave, is the
            // answer (the search does not improve on it), and the file reads back.
            let origin = v["structured"]["origin"].as_str().unwrap_or_default();
            assert!(origin.contains("alternating triangle wave"), "{v}");
            let written = write(dir.path(), "chain12.json", &v.to_string());
            let out = crawlopt(&["certify", written.to_str().unwrap()]);
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
}

/// The file's input replaced by `times` and `values` (piecewise constant).
fn with_input(text: &str, times: &str, values: &[Vec<f64>]) -> GeneralFile {
    let head = text.split("[input]").next().unwrap();
    let rows: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
    GeneralFile::parse(&format!(
        "{head}[input]\nkind = \"piecewise_constant\"\ntimes = {times}\nvalues = [{}]\n",
        rows.join(", ")
    ))
    .unwrap()
}

/// A 6-block chain of uneven stiffness and thresholds under an uneven input: rates with zero
/// mean over T = 10 (4 u0 + 3 u1 + 3 u2 = 0 per link), not a wave: each link its own pattern.
fn uneven_chain() -> GeneralFile {
    let k = [1.0, 2.0, 0.7, 1.5, 1.2];
    let mp = [1.0, 1.1, 0.9, 1.2, 1.0, 1.05];
    let mm = [1.5, 1.3, 1.7, 1.4, 1.6, 1.35];
    let (u0, u1) = ([0.6, -0.3, 0.5, 0.2, -0.9], [-0.4, 1.0, -1.0, -0.9, 0.4]);
    let u2: Vec<f64> = (0..5).map(|l| -(4.0 * u0[l] + 3.0 * u1[l]) / 3.0).collect();
    assert!(u2.iter().all(|v| v.abs() <= 1.0), "{u2:?}");
    with_input(
        &chain_text(&k, &mp, &mm),
        "[0.0, 4.0, 7.0]",
        &[u0.to_vec(), u1.to_vec(), u2],
    )
}

/// On a chain the periodic regime is searched by the crawler's simulator and the period played
/// from it by the general one: the same `J` as the general simulator's own plain iteration from
/// the origin (an independent method), on a heterogeneous chain under an uneven input and on
/// the uniform 20-block chain, there in a few periods where the plain iteration takes hundreds.
#[test]
fn a_chains_regime_is_searched_by_the_crawlers_simulator() {
    let uneven = uneven_chain();
    for (file, long) in [(uneven, false), (uniform(20, 1.3), true)] {
        let s = simulate_general(&file, &GeneralSimOptions::DEFAULT).unwrap();
        assert_eq!(s.regime_search, "chain");
        let (p, _) = crawlopt::api::general_problem(&file).unwrap();
        let input = file.input(&p).unwrap();
        let origin = vec![0.0; p.states()];
        let plain = simulate_general_exact(&p, &input, &origin, 5000, 1e-12).unwrap();
        let (a, b) = (s.objective.unwrap(), plain.objective.unwrap());
        assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{a} vs {b}");
        // The crawler's search counts its periods too; on a short chain the transient is short
        // (the 6 blocks: 45 against 44), on a long one the Newton steps shorten it.
        assert!(
            !long || 10 * s.simulation.periods < plain.periods,
            "{} vs {}",
            s.simulation.periods,
            plain.periods
        );
        println!(
            "J = {a:.12} in {} periods (plain: {b:.12} in {})",
            s.simulation.periods, plain.periods
        );
    }
}

/// Where the crawler's simulator does not apply the general one iterates plainly: a
/// piecewise-linear input (catching-up, its steps still projected by the chain's method), and a
/// problem that is not a chain (the one-link example with a drift).
#[test]
fn the_plain_search_where_the_chain_does_not_apply() {
    let text = uniform_text(12, 1.3).replace("piecewise_constant", "piecewise_linear");
    let s = simulate_general(
        &GeneralFile::parse(&text).unwrap(),
        &GeneralSimOptions::DEFAULT,
    )
    .unwrap();
    assert_eq!((s.method, s.regime_search), ("catching-up", "plain"));
    assert_eq!(s.simulation.projection, "chain");
    let drift = GeneralFile::load_if_general("examples/general_drift.toml".as_ref())
        .unwrap()
        .unwrap();
    let s = simulate_general(&drift, &GeneralSimOptions::DEFAULT).unwrap();
    assert_eq!(s.regime_search, "plain");
    let s = simulate_general(&drift, &catching_up()).unwrap();
    assert_eq!(
        (s.regime_search, s.simulation.projection),
        ("plain", "dense")
    );
}

fn catching_up() -> GeneralSimOptions {
    GeneralSimOptions {
        method: GeneralMethod::CatchingUp,
        ..GeneralSimOptions::DEFAULT
    }
}

/// `p` with its first two states swapped: the same problem (the same `J` for the same input),
/// but no longer recognised as a chain (block 2's normal then has entries on states 1 and 3),
/// so simulated by the dense projection and the plain iteration alone.
fn disguised(p: &GeneralProblem) -> GeneralProblem {
    let mut q = p.clone();
    for row in q.c.normals.iter_mut() {
        row.swap(0, 1);
    }
    q.dynamics.b.swap(0, 1);
    assert!(q.as_chain().is_none());
    q
}

/// Catching-up on a chain: the regime searched by the crawler's catching-up scheme and every
/// step projected by the chain's O(N) method give the `J` of the same problem in disguise
/// ([`disguised`]: dense projections, plain iteration from the origin, an independent path),
/// on the heterogeneous 6-block chain under an uneven input and on the uniform 20-block chain,
/// where the wave's catching-up value is the closed form `4 - 1/19` (its knots are on the
/// steps); the chain's search in a few periods where the plain one takes hundreds.
#[test]
fn catching_up_on_a_chain_projects_and_searches_with_the_chains_kernels() {
    let uneven = uneven_chain();
    for (file, long) in [(uneven, false), (uniform(20, 1.3), true)] {
        let s = simulate_general(&file, &catching_up()).unwrap();
        assert_eq!(
            (s.method, s.regime_search, s.simulation.projection),
            ("catching-up", "chain", "chain")
        );
        let (p, _) = crawlopt::api::general_problem(&file).unwrap();
        let input = file.input(&p).unwrap();
        let q = disguised(&p);
        let dense = crawlopt::integrate::simulate_general(
            &q,
            &input,
            &vec![0.0; q.states()],
            &catching_up(),
        )
        .unwrap();
        assert_eq!(dense.projection, "dense");
        let (a, b) = (s.objective.unwrap(), dense.objective.unwrap());
        assert!((a - b).abs() <= 1e-9 * b.abs().max(1.0), "{a} vs {b}");
        if long {
            assert!((a - (4.0 - 1.0 / 19.0)).abs() <= 1e-9, "{a}");
            assert!(
                10 * s.simulation.periods < dense.periods,
                "{} vs {}",
                s.simulation.periods,
                dense.periods
            );
        }
        println!(
            "J = {a:.12} in {} periods (dense, plain: {b:.12} in {})",
            s.simulation.periods, dense.periods
        );
    }
}

/// Where the crawler's simulator refuses the input (a single knot: a constant control) or its
/// state is not confirmed by the general simulator within its few periods (a tolerance of
/// 1e-16, below what the crawler's search reaches), the general simulator searches plainly, as
/// before: the same answer as its own iteration, never an error the plain search would not
/// give.
#[test]
fn the_plain_search_takes_over_where_the_chains_does_not_hold() {
    let text = chain_text(&[1.0; 2], &[1.0; 3], &[1.3; 3]);
    let one = with_input(&text, "[0.0]", &[vec![0.0, 0.0]]);
    let s = simulate_general(&one, &GeneralSimOptions::DEFAULT).unwrap();
    assert_eq!(s.regime_search, "plain");
    assert_eq!(s.objective, Some(0.0));
    let file = uneven_chain();
    let opts = GeneralSimOptions {
        tol: 1e-16,
        ..GeneralSimOptions::DEFAULT
    };
    let s = simulate_general(&file, &opts).unwrap();
    let (p, _) = crawlopt::api::general_problem(&file).unwrap();
    let input = file.input(&p).unwrap();
    let plain = simulate_general_exact(&p, &input, &vec![0.0; p.states()], 5000, 1e-16).unwrap();
    assert!(plain.converged);
    let (a, b) = (s.objective.unwrap(), plain.objective.unwrap());
    assert!(
        (a - b).abs() <= 1e-12 * b.abs().max(1.0),
        "{a} vs {b} ({})",
        s.regime_search
    );
    assert!(
        s.simulation.periods <= opts.max_periods + 20,
        "{}",
        s.simulation.periods
    );
}

/// The crawler's search is held to the general simulator's criterion of repetition (`x~`
/// within `tol` times C's scale, up to N times tighter than the crawler's own on its state
/// `K^(1/2) x~`): on 30 blocks of alternating stiffness 0.3 and 2.7 under the wave, its state
/// was not confirmed within the replay's 20 periods and the plain search took 2652 (exact) and
/// 2662 (catching-up) periods; both now take the chain's, with the exact method's `J` that of
/// the plain iteration.
#[test]
fn the_chains_search_meets_the_general_criterion_on_uneven_stiffness() {
    let k: Vec<f64> = (0..29)
        .map(|l| if l % 2 == 0 { 0.3 } else { 2.7 })
        .collect();
    let file = GeneralFile::parse(&chain_text(&k, &[1.0; 30], &[1.3; 30])).unwrap();
    for opts in [GeneralSimOptions::DEFAULT, catching_up()] {
        let s = simulate_general(&file, &opts).unwrap();
        assert_eq!(s.regime_search, "chain", "{}", s.method);
        assert!(s.simulation.periods < 100, "{}", s.simulation.periods);
    }
    let s = simulate_general(&file, &GeneralSimOptions::DEFAULT).unwrap();
    let (p, _) = crawlopt::api::general_problem(&file).unwrap();
    let input = file.input(&p).unwrap();
    let plain = simulate_general_exact(&p, &input, &vec![0.0; p.states()], 5000, 1e-12).unwrap();
    let (a, b) = (s.objective.unwrap(), plain.objective.unwrap());
    assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} vs {b}");
}

/// A chain whose thresholds nearly balance (one link, `mu_1^+ - mu_2^-` of 1.5e-9 relative):
/// C's vertex enumeration accepts it, the crawler's projection (relative `1e-9`) does not, so
/// catching-up projects densely where it was refused with exit 2 naming the uniqueness
/// condition; the same `J` as the exact method.
#[test]
fn a_nearly_balanced_chain_is_projected_densely() {
    let file = GeneralFile::parse(
        "[sweeping_process]\nnormals = [[-1.0], [1.0], [1.0], [-1.0]]\n\
         offsets = [0.50000000075, 0.7, 0.55, 0.5]\n[dynamics]\nB = [[1.0]]\n\
         [control]\nlower = [-1.5]\nupper = [1.5]\n\
         [objective]\nface_weights = [0.5, -0.5, 0.5, -0.5]\n[problem]\nperiod = 10.0\n\
         [input]\nkind = \"piecewise_constant\"\ntimes = [0.0, 3.3, 6.1]\n\
         values = [[1.0], [-1.2], [0.0153846153846154]]\n",
    )
    .unwrap();
    let s = simulate_general(&file, &catching_up()).unwrap();
    assert_eq!(s.simulation.projection, "dense");
    let exact = simulate_general(&file, &GeneralSimOptions::DEFAULT).unwrap();
    let (a, b) = (s.objective.unwrap(), exact.objective.unwrap());
    assert!((a - b).abs() <= 1e-9, "{a} vs {b}");
}

/// `optimize --method local` on a chain (4 blocks, uneven stiffness, thresholds and scale):
/// the chain's projection gave a free block's rounding (1e-16) as a reaction on a face far from
/// the state, which the local method took for a held face in its start branch, and its LP
/// had no feasible point (exit 2). Reactions now come from the projection's working set only.
#[test]
fn the_local_method_starts_from_a_chains_simulation() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "chain4.toml", CHAIN4);
    for m in ["4", "6"] {
        let v = common::optimize_json(&file, &["--method", "local", "--m", m]);
        assert_eq!(v["solution"]["stop"], "stationary", "{v}");
    }
}

const CHAIN4: &str = r#"[sweeping_process]
normals = [[-1.0, 0.0, 0.0], [1.0, -0.0, -0.0], [0.19008136006754056, -0.981768341593308, 0.0], [-0.19008136006754056, 0.981768341593308, -0.0], [0.0, 0.7714546003353933, -0.6362843700904169], [-0.0, -0.7714546003353933, 0.6362843700904169], [0.0, 0.0, 1.0], [-0.0, -0.0, -1.0]]
offsets = [0.7648443238049135, 1.8794937560862293, 0.24081397200121657, 0.08137848039912611, 0.1748936029857683, 0.043507527988652914, 0.3739589763055117, 0.46425981919633824]
[dynamics]
B = [[2.3207895265951737, 0.0, 0.0], [0.0, 0.44933087670131194, 0.0], [0.0, 0.0, 0.5447853007212871]]
[control]
lower = [-1.8655341358101067, -2.5245601649158838, -1.0042121067022214]
upper = [1.8655341358101067, 2.5245601649158838, 1.0042121067022214]
zero_mean = true
[objective]
face_weights = [0.5801973816487934, -0.5801973816487934, 0.11028470741142854, -0.11028470741142854, 0.08665959297599063, -0.08665959297599063, 0.13619632518032176, -0.13619632518032176]
[problem]
period = 8.11771035838361
[input]
kind = "piecewise_constant"
times = [0.0, 0.8298504602980575, 4.798812362704137]
values = [[-0.38265913742484614, -2.3983321566700893, 0.06383858989939628], [-1.401976613657762, 0.5129345141315917, 0.13802519843117017], [1.7722574290196014, -0.013727599015234453, -0.18102190490345188]]
"#;
