//! Progress of a long render on the terminal.

/// A progress bar over a render's samples per pixel (drawn on stderr when it is a terminal).
pub fn spp_progress_bar(spp: u64) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(spp);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} spp  {elapsed_precise} eta {eta}")
            .expect("static template"),
    );
    bar
}
