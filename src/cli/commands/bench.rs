//! `crawlopt bench`: [`crawlopt::api::bench`] as a Markdown table or JSON lines.

use crate::output::{json_line_sorted, outln};
use crate::parse::count;
use clap::Args;
use crawlopt::api::{self, BenchSettings, Naming};
use crawlopt::present::text::num;
use crawlopt::Error;
use std::process::ExitCode;

#[derive(Args)]
pub struct BenchArgs {
    /// Numbers of blocks, comma separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "3,10,100,1000",
        allow_hyphen_values = true,
        value_parser = count
    )]
    pub blocks: Vec<usize>,
    /// Time steps per period.
    #[arg(long, default_value_t = 1000, allow_negative_numbers = true, value_parser = count)]
    pub steps: usize,
    /// Amplitude A.
    #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
    pub amplitude: f64,
    /// Phase lag phi between consecutive links, degrees.
    #[arg(long = "phase-deg", default_value_t = 90.0, allow_hyphen_values = true)]
    pub phase_deg: f64,
    /// mu^+ on every block.
    #[arg(long = "mu-forward", default_value_t = 1.0, allow_hyphen_values = true)]
    pub mu_forward: f64,
    /// mu^- on every block.
    #[arg(
        long = "mu-backward",
        default_value_t = 3.3,
        allow_hyphen_values = true
    )]
    pub mu_backward: f64,
    /// Minimum measured time per case, seconds.
    #[arg(long = "min-time", default_value_t = 1.0, allow_hyphen_values = true)]
    pub min_time: f64,
    /// Integrate exactly this many periods from x = 0 (plain iteration, as a peer would) and
    /// report the displacement of the last one, instead of searching for the periodic regime.
    #[arg(long, allow_negative_numbers = true, value_parser = count)]
    pub periods: Option<usize>,
    /// Search with Anderson acceleration alone (no Newton-Krylov steps), for comparison.
    #[arg(long = "no-newton")]
    pub no_newton: bool,
    /// Print JSON lines.
    #[arg(long)]
    pub json: bool,
}

pub fn run(a: BenchArgs) -> Result<ExitCode, Error> {
    let settings = BenchSettings {
        blocks: a.blocks,
        steps: a.steps,
        amplitude: a.amplitude,
        phase_deg: a.phase_deg,
        mu_forward: a.mu_forward,
        mu_backward: a.mu_backward,
        min_time: a.min_time,
        periods: a.periods,
        newton: !a.no_newton,
        naming: Naming::Flags,
    };
    let s = &settings;
    let mut header = !a.json;
    api::bench(s, &mut |case| {
        if std::mem::take(&mut header) {
            outln(&format!(
                "sine gait L_l = {} sin(2 pi t - l {} deg), k = 1, mu+ = {}, mu- = {}, {} steps/period",
                num(s.amplitude, 0.0),
                num(s.phase_deg, 0.0),
                num(s.mu_forward, 0.0),
                num(s.mu_backward, 0.0),
                s.steps
            ));
            outln("| N | method | disp/period | periods | tangent | steps | us/step | link-steps/s | s/answer |");
            outln("|---|---|---|---|---|---|---|---|---|");
        }
        if a.json {
            json_line_sorted(case);
        } else {
            outln(&format!(
                "| {} | {} | {} | {} | {} | {} | {:.3} | {:.3e} | {:.3} |",
                case.blocks,
                case.method,
                case.disp_per_period
                    .map_or("not converged".into(), |d| format!("{d:.15}")),
                case.periods,
                case.tangent_products,
                case.periods * s.steps,
                case.us_per_step,
                case.link_steps_per_s,
                case.seconds,
            ));
        }
    })?;
    Ok(ExitCode::SUCCESS)
}
