//! The library's errors in the command's words: each names the flag that set what went wrong,
//! and says which flag would make it work.

use penumbra::{MAX_SAMPLES, MissingGpu, RenderError, Runs};

/// `error` as the command tells it. `samples_flag` is the flag that gave the light samples
/// (`--samples`, or `accuracy`'s `--technique-samples`).
pub(crate) fn render_error(error: RenderError, samples_flag: &str) -> anyhow::Error {
    let said = match &error {
        RenderError::BadSamples { samples } => format!(
            "{samples_flag} {samples} must be a positive perfect square (64, 256, 1024, ...) up to {MAX_SAMPLES}"
        ),
        RenderError::NoSamples { technique } => format!(
            "--jitter: {technique} takes no light samples (depth-complexity does; the reference always jitters)"
        ),
        RenderError::NeedsGpu {
            technique,
            missing: MissingGpu::CpuChosen,
        } => format!("--backend cpu: {technique} is a shadow-map technique and runs on a GPU only"),
        RenderError::CpuOnly { .. } => format!("--backend gpu: {error}"),
        RenderError::GpuSamples { .. } => format!("{error}; --backend cpu renders it"),
        RenderError::TooLargeForGpu { technique, .. } if Runs::of(*technique) != Runs::GpuOnly => {
            format!("{error}; --backend cpu renders it")
        }
        _ => return error.into(),
    };
    anyhow::Error::msg(said)
}

/// A result's library error in the command's words, with `--samples` the samples' flag.
pub(crate) trait InCommandWords<T> {
    /// The result, its error told as the command tells it ([`render_error`]).
    fn in_command_words(self) -> anyhow::Result<T>;
}

impl<T> InCommandWords<T> for Result<T, RenderError> {
    fn in_command_words(self) -> anyhow::Result<T> {
        self.map_err(|e| render_error(e, "--samples"))
    }
}
