//! The fuzz property over general-problem files (issue 30): structured edits of a problem (P)
//! (extremes such as 1e308, 1e-300 and a huge `A`, duplicated faces, many faces up to one beyond
//! the limit, weights scaled, whitespace and comments in the layout), then the generic
//! mutations one case in four; every answer checked for non-finite numbers.

use super::*;

/// A general problem file as data, rendered to TOML by [`GeneralDoc::render`].
#[derive(Debug, Clone)]
struct GeneralDoc {
    normals: Vec<Vec<f64>>,
    offsets: Vec<f64>,
    a: Vec<Vec<f64>>,
    b: Vec<Vec<f64>>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    /// Face weights (else reaction weights `[1, 0, ...]`).
    face_weights: Option<Vec<f64>>,
    cost: f64,
    period: f64,
    times: Vec<f64>,
    values: Vec<Vec<f64>>,
}

/// The seeds: the one-link problem of §4, the drift example's box with a stiff-capable `A`,
/// and a hexagon with reaction weights.
fn general_docs() -> Vec<GeneralDoc> {
    let one_link = GeneralDoc {
        normals: vec![vec![1.0], vec![-1.0]],
        offsets: vec![1.0, 1.0],
        a: vec![vec![0.0]],
        b: vec![vec![1.0]],
        lower: vec![-1.0],
        upper: vec![1.0],
        face_weights: Some(vec![0.5, 0.5]),
        cost: 0.0,
        period: 10.0,
        times: vec![0.0, 5.0],
        values: vec![vec![1.0], vec![-1.0]],
    };
    let square = GeneralDoc {
        normals: vec![
            vec![1.0, 0.0],
            vec![0.0, 1.0],
            vec![-1.0, 0.0],
            vec![0.0, -1.0],
        ],
        offsets: vec![1.0; 4],
        a: vec![vec![-0.5, 0.0], vec![0.0, -0.5]],
        b: vec![vec![1.0, 0.0], vec![0.0, 1.0]],
        lower: vec![-1.0, -1.0],
        upper: vec![1.0, 1.0],
        face_weights: Some(vec![1.0, 0.0, 0.0, 0.0]),
        cost: 0.1,
        period: 10.0,
        times: vec![0.0, 2.5, 5.0, 7.5],
        values: vec![
            vec![1.0, 0.5],
            vec![1.0, -0.5],
            vec![-1.0, -0.5],
            vec![-1.0, 0.5],
        ],
    };
    let mut hexagon = square.clone();
    hexagon.normals = polygon_normals(6);
    hexagon.offsets = vec![1.0; 6];
    hexagon.face_weights = None;
    vec![one_link, square, hexagon]
}

fn polygon_normals(k: usize) -> Vec<Vec<f64>> {
    (0..k)
        .map(|j| {
            let t = std::f64::consts::TAU * j as f64 / k as f64;
            vec![t.cos(), t.sin()]
        })
        .collect()
}

/// A structured edit of a [`GeneralDoc`].
#[derive(Debug, Clone)]
enum GeneralEdit {
    /// One entry of a field (0 normals, 1 offsets, 2 A, 3 B, 4 weights, 5 bounds, 6 period,
    /// 7 cost, 8 input values) set to an extreme.
    Extreme { field: u8, at: u16, with: u8 },
    /// Face `face` (mod sigma) repeated `times` more times.
    Duplicate { face: u8, times: u8 },
    /// C as a regular polygon of `GENERAL_FACES[k]` faces (2-d seeds).
    Faces { k: u8 },
    /// `A = diag(-10^e, s 10^e, ...)` (`s` the sign of the second entry).
    Stiff { exp: u16, unstable: bool },
    /// Every weight times `10^e`.
    ScaleWeights { exp: i16 },
}

/// Extremes of a general file's numbers.
const GENERAL_EXTREMES: &[f64] = &[
    1e308, -1e308, 1e-300, -1e-300, 1.7e308, 5e-324, 0.0, -0.0, 1e20, 1e-20, 1e12, -1e12,
];
/// Face counts of [`GeneralEdit::Faces`] (one beyond the limit).
const GENERAL_FACES: &[usize] = &[3, 5, 64, 300, crawlopt::model::general::MAX_FACES + 1];

fn general_edit_strategy() -> impl Strategy<Value = GeneralEdit> {
    prop_oneof![
        6 => (0u8..9, any::<u16>(), 0..GENERAL_EXTREMES.len() as u8)
            .prop_map(|(field, at, with)| GeneralEdit::Extreme { field, at, with }),
        2 => (any::<u8>(), 1u8..4).prop_map(|(face, times)| GeneralEdit::Duplicate { face, times }),
        1 => (0..GENERAL_FACES.len() as u8).prop_map(|k| GeneralEdit::Faces { k }),
        3 => (0u16..309, any::<bool>()).prop_map(|(exp, unstable)| GeneralEdit::Stiff { exp, unstable }),
        1 => (-320i16..320).prop_map(|exp| GeneralEdit::ScaleWeights { exp }),
    ]
}

impl GeneralDoc {
    fn apply(&mut self, e: &GeneralEdit) {
        let n = self.normals[0].len();
        let pick = |len: usize, at: u16| at as usize % len.max(1);
        match *e {
            GeneralEdit::Extreme { field, at, with } => {
                let v = GENERAL_EXTREMES[with as usize];
                let flat = |m: &mut Vec<Vec<f64>>, at: u16| {
                    let cols = m[0].len();
                    let k = pick(m.len() * cols, at);
                    m[k / cols][k % cols] = v;
                };
                match field {
                    0 => flat(&mut self.normals, at),
                    1 => {
                        let k = pick(self.offsets.len(), at);
                        self.offsets[k] = v;
                    }
                    2 => flat(&mut self.a, at),
                    3 => flat(&mut self.b, at),
                    4 => {
                        if let Some(w) = &mut self.face_weights {
                            let k = pick(w.len(), at);
                            w[k] = v;
                        }
                    }
                    5 => {
                        let k = pick(self.lower.len(), at);
                        if at % 2 == 0 {
                            self.lower[k] = -v.abs();
                        } else {
                            self.upper[k] = v.abs();
                        }
                    }
                    6 => self.period = v,
                    7 => self.cost = v,
                    _ => flat(&mut self.values, at),
                }
            }
            GeneralEdit::Duplicate { face, times } => {
                let j = face as usize % self.normals.len();
                for _ in 0..times {
                    self.normals.push(self.normals[j].clone());
                    self.offsets.push(self.offsets[j]);
                    if let Some(w) = &mut self.face_weights {
                        w.push(w[j]);
                    }
                }
            }
            GeneralEdit::Faces { k } => {
                if n == 2 {
                    let k = GENERAL_FACES[k as usize];
                    self.normals = polygon_normals(k);
                    self.offsets = vec![1.0; k];
                    if let Some(w) = &mut self.face_weights {
                        *w = (0..k).map(|j| if j == 0 { 1.0 } else { 0.0 }).collect();
                    }
                }
            }
            GeneralEdit::Stiff { exp, unstable } => {
                let r = 10f64.powi(i32::from(exp));
                for (i, row) in self.a.iter_mut().enumerate() {
                    row.iter_mut().for_each(|v| *v = 0.0);
                    row[i] = if i == 1 && unstable { r } else { -r };
                }
            }
            GeneralEdit::ScaleWeights { exp } => {
                let s = 10f64.powi(i32::from(exp));
                if let Some(w) = &mut self.face_weights {
                    w.iter_mut().for_each(|v| *v *= s);
                }
            }
        }
    }

    /// TOML, with `ws` choosing the layout (compact, spread over lines with comments, tabs).
    fn render(&self, ws: u8) -> String {
        let (sep, open, close) = match ws % 4 {
            0 => (", ", "[", "]"),
            1 => (",\n  ", "[\n  ", ",\n]"),
            2 => (" ,\t", "[ \t", " ]"),
            _ => (", # a comment\n", "[ # open\n", "\n]"),
        };
        let num = |v: &f64| format!("{v:?}");
        let row = |r: &[f64]| format!("[{}]", r.iter().map(num).collect::<Vec<_>>().join(", "));
        let vec = |r: &[f64]| {
            format!(
                "{open}{}{close}",
                r.iter().map(num).collect::<Vec<_>>().join(sep)
            )
        };
        let mat = |m: &[Vec<f64>]| {
            format!(
                "{open}{}{close}",
                m.iter().map(|r| row(r)).collect::<Vec<_>>().join(sep)
            )
        };
        let n = self.normals[0].len();
        let reward = match &self.face_weights {
            Some(w) => format!("face_weights = {}", vec(w)),
            None => format!(
                "reaction_weights = {}",
                vec(&(0..n)
                    .map(|i| if i == 0 { 1.0 } else { 0.0 })
                    .collect::<Vec<_>>())
            ),
        };
        let pad = if ws % 2 == 1 { "\n\n" } else { "\n" };
        format!(
            "[sweeping_process]\nnormals = {}\noffsets = {}{pad}[dynamics]\nA = {}\nB = {}{pad}\
             [control]\nlower = {}\nupper = {}\nzero_mean = true{pad}[objective]\n{reward}\n\
             cost = {{ kind = \"quadratic\", weight = {} }}{pad}[problem]\nperiod = {}{pad}\
             [input]\nkind = \"piecewise_constant\"\ntimes = {}\nvalues = {}\n",
            mat(&self.normals),
            vec(&self.offsets),
            mat(&self.a),
            mat(&self.b),
            vec(&self.lower),
            vec(&self.upper),
            num(&self.cost),
            num(&self.period),
            vec(&self.times),
            mat(&self.values),
        )
    }
}

/// The invariant of every answer on a general file: no non-finite number reported (issue 30,
/// item 3), no periodic regime without its `J`. A violation panics inside the step (a failure).
fn general_answers(s: &Steps, file: &crawlopt::io::GeneralFile) {
    use crawlopt::api;
    s.step("api::analyze_general", || api::analyze_general(file));
    let opts = crawlopt::integrate::GeneralSimOptions {
        steps_per_period: 64,
        max_periods: 50,
        ..Default::default()
    };
    s.step("api::simulate_general (finite answer)", || {
        let r = api::simulate_general(file, &opts)?;
        let sim = &r.simulation;
        if sim.converged {
            let j = sim.objective.expect("a periodic regime without J");
            assert!(
                j.is_finite() && sim.reward.is_finite() && sim.cost.is_finite(),
                "J = {j}"
            );
        }
        assert!(
            sim.x.iter().flatten().all(|v| v.is_finite()),
            "a state is not finite"
        );
        assert!(
            sim.lambda.iter().flatten().all(|v| v.is_finite()),
            "a reaction is not finite"
        );
        Ok::<_, crawlopt::Error>(())
    });
    let pm = api::GeneralPmSettings {
        m: 2,
        time_limit: Some(1.0),
        ..api::GeneralPmSettings::default()
    };
    s.step("api::optimize_general (finite answer)", || {
        let r = api::optimize_general(file, &pm, crawlopt::api::Hooks::default())?;
        let o = r.solution.objective();
        assert!(o.is_finite(), "P_m's J = {o}");
        Ok::<_, crawlopt::Error>(())
    });
}

/// General-problem files: structured edits (extremes such as 1e308, 1e-300 and a huge `A`,
/// duplicated faces, many faces up to one beyond the limit, weights scaled, the layout's
/// whitespace and comments), and one case in four a generic mutation of the result, through the
/// library's jobs with the finite-answer invariant and, one case in four, `simulate --json`.
#[test]
fn fuzz_general_files() {
    let docs = general_docs();
    let dir = case_dir("general");
    drive(
        "general",
        120,
        (
            0..docs.len(),
            proptest::collection::vec(general_edit_strategy(), 0..4),
            any::<u8>(),
            mutation_strategy(),
        ),
        |(i, edits, variant, m), stats| {
            let mut doc = docs[*i].clone();
            edits.iter().for_each(|e| doc.apply(e));
            let text = doc.render(*variant);
            let bytes = if variant % 4 == 3 {
                Seed::new("general.toml", text, Syntax::Toml).render(m)
            } else {
                text.into_bytes()
            };
            let files: Files = vec![("general.toml".into(), bytes)];
            let d = dir.path();
            write_files(d, &files);
            let path = d.join("general.toml");
            let steps = in_process(QUICK, move |s: &Steps| {
                if let Some(Some(file)) = s.step("GeneralFile::load_if_general", || {
                    crawlopt::io::GeneralFile::load_if_general(&path)
                }) {
                    general_answers(s, &file);
                }
            });
            let mut failure = outcome_of(&steps, stats, "in-process");
            if failure.is_none() && (variant / 4) % 4 == 0 {
                let run = run_bin(d, &["simulate", "general.toml", "--json"], QUICK);
                failure = judge_bin("simulate", &run, &[3], stats);
                if failure.is_none() && run.outcome == Outcome::Exit(0) {
                    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
                    let sim = &v["simulation"];
                    if sim["converged"] == true && !sim["objective"].is_f64() {
                        failure = Some(Failure {
                            signature: "simulate: converged without a finite J".into(),
                            detail: run.stdout.chars().take(400).collect(),
                        });
                    }
                }
            }
            (files, failure)
        },
    );
}
