//! DejaVu Sans embedded in the binary and registered with plotters once (licence:
//! `assets/fonts/DejaVuSans.LICENSE`).

use std::sync::Once;

static FONT: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

pub(crate) fn ensure_registered() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The font is a valid TrueType file shipped with the source; registration cannot fail
        // for it, and if it ever did the plots would still draw (without text).
        let _ =
            plotters::style::register_font("sans-serif", plotters::style::FontStyle::Normal, FONT);
    });
}
