//! What identifies a render: every input that changes its image, as one `name=value` field per
//! line. Checkpoints (`--resume`) and parts (`prism merge`) combine only when their fingerprints
//! are equal, so samples of unlike renders are never summed into one image.

use crate::pbrt::InputStamp;
use crate::render::{RenderSettings, SAMPLE_STREAM_VERSION};

/// The fingerprint of rendering `scene` (a built-in scene's name, or the scene file's name),
/// whose files are `inputs` (none for a built-in scene), with `settings`, written in the colour
/// space `color_space` and intersected by the backend `accel`. The time limit, thread count and
/// output path are left out: they change how long a render runs, not what a sample adds.
pub fn fingerprint(
    scene: &str,
    inputs: &[InputStamp],
    settings: &RenderSettings,
    color_space: &str,
    accel: &str,
) -> String {
    let mut fields = vec![format!("scene={scene}")];
    for i in inputs {
        let bytes = i.bytes.map_or("unreadable".to_string(), |b| b.to_string());
        fields.push(format!("input {}={bytes}:{}", i.file, i.xxh3.as_deref().unwrap_or("-")));
    }
    let st = settings;
    fields.extend([
        format!("resolution={}x{}", st.resolution.0, st.resolution.1),
        format!("film={:?}", st.film),
        format!("spp={}", st.spp),
        format!("seed={}", st.seed),
        format!("sampler={:?} v{SAMPLE_STREAM_VERSION}", st.sampler),
        format!("filter={:?}", st.filter),
        format!("integrator={:?}", st.integrator),
        format!("color space={color_space}"),
        format!("accel={accel}"),
        format!("prism={}", env!("CARGO_PKG_VERSION")),
    ]);
    fields.join("\n")
}

/// The first field in which fingerprint `a` differs from `b`, as "name (a vs b)"; `None` if they
/// are equal. Fields are matched by name, so a missing input file is named too.
pub fn difference(a: &str, b: &str) -> Option<String> {
    let fields = |s: &'_ str| -> Vec<(String, String)> {
        s.lines().map(|f| f.split_once('=').unwrap_or((f, ""))).map(|(n, v)| (n.into(), v.into())).collect()
    };
    let (fa, fb) = (fields(a), fields(b));
    let value = |fs: &[(String, String)], name: &str| fs.iter().find(|(n, _)| n == name).map(|(_, v)| v.clone());
    for (name, va) in &fa {
        match value(&fb, name) {
            Some(vb) if &vb == va => {}
            Some(vb) => return Some(format!("{name} ({va} vs {vb})")),
            None => return Some(format!("{name} ({va} vs none)")),
        }
    }
    fb.iter().find(|(n, _)| value(&fa, n).is_none()).map(|(n, v)| format!("{n} (none vs {v})"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_difference_names_the_first_unequal_field() {
        let a = "scene=s.pbrt\ninput s.pbrt=10:aa\nspp=4";
        assert_eq!(difference(a, a), None);
        assert_eq!(difference(a, "scene=s.pbrt\ninput s.pbrt=10:ab\nspp=4").unwrap(), "input s.pbrt (10:aa vs 10:ab)");
        assert_eq!(difference(a, "scene=s.pbrt\nspp=4").unwrap(), "input s.pbrt (10:aa vs none)");
        let extra = format!("{a}\ninput m.ply=3:cc");
        assert_eq!(difference(a, &extra).unwrap(), "input m.ply (none vs 3:cc)");
    }
}
