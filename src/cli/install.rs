//! `nostencil layer install` / `uninstall`: the fill-rate layer for this user, where the Vulkan
//! loader looks for explicit layers (LoaderLayerInterface.md, "Linux Layer Discovery":
//! `$XDG_DATA_HOME/vulkan/explicit_layer.d`, by default `~/.local/share/...`), with its library
//! in `~/.local/lib/nostencil/`. Then `VK_INSTANCE_LAYERS=VK_LAYER_NOSTENCIL_fillrate` turns it on
//! for any program, as for MangoHud or the validation layer.

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use nostencil_fillrate_report::manifest::{manifest_json, newest_library, GL_SWAPS_FILE, LIBRARY_FILE, MANIFEST_FILE};

/// Where an installed layer lives for the user whose environment `var` reads.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InstallPaths {
    pub manifest: PathBuf,
    pub library: PathBuf,
}

impl InstallPaths {
    /// From `$XDG_DATA_HOME` (else `$HOME/.local/share`) and `$HOME`.
    pub fn from_env(var: impl Fn(&str) -> Option<String>) -> Result<Self> {
        let home = var("HOME").filter(|h| !h.is_empty()).map(PathBuf::from);
        // The loader, like the XDG spec, ignores a relative XDG_DATA_HOME.
        let data = var("XDG_DATA_HOME").map(PathBuf::from).filter(|p| p.is_absolute());
        let (data, home) = match (data, home) {
            (Some(data), Some(home)) => (data, home),
            (None, Some(home)) => (home.join(".local/share"), home),
            (_, None) => {
                return Err(Error::InvalidInput("HOME is not set: no user folder to install the layer in".into()))
            }
        };
        Ok(InstallPaths {
            manifest: data.join("vulkan/explicit_layer.d").join(MANIFEST_FILE),
            library: home.join(".local/lib/nostencil").join(LIBRARY_FILE),
        })
    }

    pub fn current() -> Result<Self> {
        Self::from_env(|name| std::env::var(name).ok())
    }

    /// Both files are there: the loader will find the layer.
    pub fn installed(&self) -> bool {
        self.manifest.is_file() && self.library.is_file()
    }
}

/// The command that installs the layer, for messages.
pub const HOW_TO_INSTALL: &str = "from nostencil's source folder: `cargo build --release && \
target/release/nostencil layer install` (or `nostencil layer install --library PATH/libnostencil_fillrate.so`, \
or an executable that carries the layer: `cargo install --path . --features embedded-layer`)";

/// The layer library this executable carries, built into it with the `embedded-layer` feature
/// (build.rs builds the layer's crate for it): what `cargo install` gives, which installs no
/// library beside the executable.
#[cfg(feature = "embedded-layer")]
const EMBEDDED_LAYER: Option<&[u8]> = Some(include_bytes!(concat!(env!("OUT_DIR"), "/libnostencil_fillrate.so")));
#[cfg(not(feature = "embedded-layer"))]
const EMBEDDED_LAYER: Option<&[u8]> = None;

/// Where the library to install comes from.
enum Source {
    File(PathBuf),
    Embedded(&'static [u8]),
}

/// The layer library to install: `library`, or the one built beside this executable, or the one
/// it carries.
fn source_library(library: Option<&Path>) -> Result<Source> {
    if let Some(path) = library {
        if !path.is_file() {
            return Err(Error::InvalidInput(format!("--library {}: no such file", path.display())));
        }
        return Ok(Source::File(path.to_path_buf()));
    }
    let exe =
        std::env::current_exe().map_err(|e| Error::Internal(format!("cannot find the nostencil executable: {e}")))?;
    let dir = exe.parent().unwrap_or(Path::new(".")).to_path_buf();
    match (newest_library(&dir), EMBEDDED_LAYER) {
        (Some(path), _) => Ok(Source::File(path)),
        (None, Some(bytes)) => Ok(Source::Embedded(bytes)),
        (None, None) => Err(Error::InvalidInput(format!(
            "no {LIBRARY_FILE} beside {} (`cargo install` installs only the executable, unless built with \
             `--features embedded-layer`); install {HOW_TO_INSTALL}",
            exe.display()
        ))),
    }
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> Error + '_ {
    move |source| Error::Io { path: path.to_path_buf(), source }
}

/// Copies the library and writes the manifest naming it by absolute path; says where.
pub fn install(library: Option<&Path>, paths: &InstallPaths) -> Result<()> {
    let source = source_library(library)?;
    for dir in [paths.library.parent(), paths.manifest.parent()].into_iter().flatten() {
        std::fs::create_dir_all(dir).map_err(io(dir))?;
    }
    // Written beside, then renamed: a program loading the old library meanwhile keeps its copy.
    let temp = paths.library.with_extension("so.new");
    let from = match &source {
        Source::File(path) => {
            std::fs::copy(path, &temp).map_err(io(&temp))?;
            path.display().to_string()
        }
        Source::Embedded(bytes) => {
            std::fs::write(&temp, bytes).map_err(io(&temp))?;
            "the copy this executable carries".to_owned()
        }
    };
    std::fs::rename(&temp, &paths.library).map_err(io(&paths.library))?;
    // The GL swap library `profile-app --gl` preloads, beside the layer, where it was built.
    if let Source::File(path) = &source {
        let swaps = path.with_file_name(GL_SWAPS_FILE);
        if let (true, Some(dir)) = (swaps.is_file(), paths.library.parent()) {
            let to = dir.join(GL_SWAPS_FILE);
            std::fs::copy(&swaps, &to).map_err(io(&to))?;
            eprintln!("installed {} (for profile-app --gl)", to.display());
        }
    }
    let text = manifest_json(&paths.library.to_string_lossy());
    crate::frame::write_atomically(&paths.manifest, text.as_bytes())?;
    eprintln!("installed {} (from {from})", paths.library.display());
    eprintln!("installed {}", paths.manifest.display());
    eprintln!(
        "turn it on for a program: VK_INSTANCE_LAYERS=VK_LAYER_NOSTENCIL_fillrate NOSTENCIL_FILLRATE_OUT=report.json \
         PROGRAM"
    );
    Ok(())
}

/// Removes what [`install`] wrote, and the folders it made once empty; says what.
pub fn uninstall(paths: &InstallPaths) -> Result<()> {
    let mut removed = 0;
    let swaps = paths.library.with_file_name(GL_SWAPS_FILE);
    for path in [&paths.manifest, &paths.library, &swaps] {
        match std::fs::remove_file(path) {
            Ok(()) => {
                eprintln!("removed {}", path.display());
                removed += 1;
            }
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(Error::Io { path: path.clone(), source: e }),
        }
    }
    // The folders install may have made, innermost first; remove_dir removes only empty ones,
    // so nothing of the user's (or another layer's) goes.
    let library_dirs = paths.library.ancestors().skip(1).take(2);
    let manifest_dirs = paths.manifest.ancestors().skip(1).take(2);
    for dir in library_dirs.chain(manifest_dirs) {
        let _ = std::fs::remove_dir(dir);
    }
    if removed == 0 {
        eprintln!("the fill-rate layer was not installed for this user ({})", paths.manifest.display());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_follow_xdg_data_home_or_home() {
        let paths = InstallPaths::from_env(|n| (n == "HOME").then(|| "/h".to_owned())).expect("paths");
        assert_eq!(paths.manifest, Path::new("/h/.local/share/vulkan/explicit_layer.d").join(MANIFEST_FILE));
        assert_eq!(paths.library, Path::new("/h/.local/lib/nostencil").join(LIBRARY_FILE));
        let xdg = |n: &str| match n {
            "HOME" => Some("/h".to_owned()),
            "XDG_DATA_HOME" => Some("/d".to_owned()),
            _ => None,
        };
        let paths = InstallPaths::from_env(xdg).expect("paths");
        assert_eq!(paths.manifest, Path::new("/d/vulkan/explicit_layer.d").join(MANIFEST_FILE));
        let relative = |n: &str| (n == "HOME" || n == "XDG_DATA_HOME").then(|| "rel".to_owned());
        assert!(InstallPaths::from_env(relative).is_ok_and(|p| p.manifest.starts_with("rel/.local/share")));
        assert!(InstallPaths::from_env(|_| None).is_err());
    }
}
