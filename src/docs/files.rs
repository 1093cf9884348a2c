//! The files an FMU carries besides `modelDescription.xml`, the scene and the library.

use super::html::index_html;
use super::licenses::license_files;
use super::png::sketch_png;
use super::terminals::{terminals, terminals_and_icons_xml};
use crate::model::{Sketch, build_model};
use crate::scene::{ParamValues, Scene};
use crate::variables::VariableTable;

/// One file inside the FMU.
#[derive(Clone, Debug, PartialEq)]
pub struct FmuFile {
    /// Path inside the archive (forward slashes).
    pub path: String,
    /// Contents.
    pub data: Vec<u8>,
}

/// Side length of `model.png` [px].
pub const ICON_SIZE: usize = 256;

/// `documentation/index.html`, `documentation/licenses/…`, `model.png` (FMI 2.0.4, 2.3) and
/// `terminalsAndIcons/` (`terminalsAndIcons.xml` and the same icon as `icon.png`, FMI 3.0
/// 2.4.9) of `scene`. Builds the model with the default
/// parameters for its drawing (as `flexfmu check` does); if that fails the page gives the
/// message instead of a drawing. Fails only if the licences were not collected at build time.
pub fn documentation_files(scene: &Scene) -> Result<Vec<FmuFile>, String> {
    // a model that does not build with the default parameters (the user sets others before
    // initialization) is still packaged; the page says why there is no drawing
    let (sketch, n_free) = match build_model(scene, &ParamValues::defaults(&scene.params)) {
        Ok(model) => (model.sketch(), Some(model.n_free())),
        Err(e) => (
            Sketch::new(format!(
                "the model does not build with the default parameters: {e}"
            )),
            None,
        ),
    };
    let ports = terminals(&VariableTable::from_scene(scene));
    let icon = sketch_png(&sketch, ICON_SIZE);
    let mut out = vec![
        FmuFile {
            path: "documentation/index.html".into(),
            data: index_html(scene, &sketch, n_free, &ports).into_bytes(),
        },
        // the FMI 2.0 icon, and the FMI 3.0 one that terminalsAndIcons.xml refers to
        FmuFile {
            path: "model.png".into(),
            data: icon.clone(),
        },
        FmuFile {
            path: "terminalsAndIcons/icon.png".into(),
            data: icon,
        },
        FmuFile {
            path: "terminalsAndIcons/terminalsAndIcons.xml".into(),
            data: terminals_and_icons_xml(&ports).into_bytes(),
        },
    ];
    for (p, data) in license_files()? {
        out.push(FmuFile {
            path: format!("documentation/licenses/{p}"),
            data,
        });
    }
    Ok(out)
}
