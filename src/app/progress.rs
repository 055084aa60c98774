//! Progress bars on stderr (indicatif draws nothing when stderr is not a terminal, e.g. in CI
//! logs).

use indicatif::{ProgressBar, ProgressStyle};

/// A bar counting `unit`s toward a total.
pub fn counting(label: &str, unit: &str) -> ProgressBar {
    let bar = ProgressBar::new(0);
    let template = format!(
        "{label} [{{bar:30}}] {{percent:>3}}% {{pos}}/{{len}} {unit}  {{elapsed}}, ETA {{eta}}"
    );
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style.progress_chars("#-"));
    }
    bar
}

/// `done` of `total`, as the path tracer and the runners report it.
pub fn update(bar: &ProgressBar, done: u32, total: u32) {
    bar.set_length(u64::from(total));
    bar.set_position(u64::from(done));
    if done >= total {
        bar.finish();
    }
}

/// A bar for a GI method's set-up: the stage it is in and its fraction done.
pub fn setup(method: &str) -> ProgressBar {
    let bar = ProgressBar::new(1000);
    let template = format!("{method} set-up [{{bar:30}}] {{percent:>3}}% {{msg}}  {{elapsed}}");
    if let Ok(style) = ProgressStyle::with_template(&template) {
        bar.set_style(style.progress_chars("#-"));
    }
    bar
}

/// Report a set-up stage to `bar` (see [`setup`]).
pub fn setup_stage(bar: &ProgressBar, stage: &str, fraction: f64) {
    bar.set_message(stage.to_string());
    bar.set_position((fraction.clamp(0.0, 1.0) * 1000.0) as u64);
}
