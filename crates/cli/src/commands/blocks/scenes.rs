//! `rollstack blocks scenes [NAME]`: the built-in scenes of `blockstack::scenes`, listed
//! or printed as TOML; and how `blocks run` finds its scene (a file, else a built-in
//! name).

use anyhow::{Context, Result};
use blockstack::scene_file::{LoadedScene, MAX_SCENE_BYTES};
use blockstack::scenes;
use clap::Args;
use std::io::Read;
use std::path::{Path, PathBuf};

/// Arguments of `rollstack blocks scenes`.
#[derive(Debug, Args)]
pub struct ScenesArgs {
    /// A built-in scene to print as TOML (to save and edit); without it, every built-in
    /// scene is listed with a one-line description.
    pub name: Option<String>,
}

/// Runs `rollstack blocks scenes`.
///
/// # Errors
/// An unknown name (the error lists the built-in names).
pub fn run(args: &ScenesArgs) -> Result<()> {
    match &args.name {
        Some(name) => print!("{}", scenes::find(name)?.toml),
        None => {
            let width = scenes::names().iter().map(|n| n.len()).max().unwrap_or(0);
            for s in scenes::builtin() {
                println!("{:width$}  {}", s.name, s.description);
            }
            println!();
            println!("`rollstack blocks scenes NAME > my.toml` prints one to start from;");
            println!("`rollstack blocks run NAME` runs one; docs/scenes.md lists every key.");
        }
    }
    Ok(())
}

/// The scene `blocks run` is given: the file at `arg` if there is one, else the built-in
/// scene of that name.
///
/// # Errors
/// An unreadable or invalid file; no such file and no such built-in scene (the error
/// names the built-in scenes).
pub fn load_scene(arg: &Path) -> Result<LoadedScene> {
    let (text, what) = scene_text(arg)?;
    LoadedScene::from_toml_at(&text, &scene_dir(arg)).with_context(|| what)
}

/// The directory where the record paths of the scene `arg` names start: the scene
/// file's, or the working directory for a built-in scene.
#[must_use]
pub fn scene_dir(arg: &Path) -> PathBuf {
    if arg.exists() && !arg.is_dir() {
        arg.parent().map(Path::to_path_buf).unwrap_or_default()
    } else {
        PathBuf::new()
    }
}

/// The TOML text of the scene `arg` names (a file, else a built-in scene), with what it
/// is for error messages (`scene my.toml`, `built-in scene shaking`). A directory is not
/// a scene: `blocks run shaking --out shaking` makes one, after which `shaking` still
/// names the built-in scene, taken with a note on stderr that says so.
///
/// # Errors
/// An unreadable file; no such file and no such built-in scene (the error names the
/// built-in scenes).
pub fn scene_text(arg: &Path) -> Result<(String, String)> {
    if arg.exists() && !arg.is_dir() {
        let text =
            read_scene_file(arg).with_context(|| format!("cannot read scene {}", arg.display()))?;
        return Ok((text, format!("scene {}", arg.display())));
    }
    let builtin = arg.to_str().and_then(|name| scenes::find(name).ok());
    let not_a_file = if arg.is_dir() {
        "is a directory, not a scene file"
    } else {
        "no such file"
    };
    match builtin {
        Some(s) => {
            if arg.is_dir() {
                eprintln!(
                    "note: {} {not_a_file}: took the built-in scene {}",
                    arg.display(),
                    s.name
                );
            }
            Ok((s.toml.to_owned(), format!("built-in scene {}", s.name)))
        }
        None => anyhow::bail!(
            "cannot read scene {}: {not_a_file}, and no built-in scene of that name (built-in scenes: {})",
            arg.display(),
            scenes::names().join(", ")
        ),
    }
}

/// The text of the scene file at `path`, read up to [`MAX_SCENE_BYTES`]: a larger file
/// (`/dev/zero`, a trajectory given by mistake) is refused, not read into memory.
///
/// # Errors
/// An unreadable or too large file, or one that is not UTF-8 text.
fn read_scene_file(path: &Path) -> Result<String> {
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(MAX_SCENE_BYTES + 1)
        .read_to_end(&mut bytes)?;
    anyhow::ensure!(
        bytes.len() as u64 <= MAX_SCENE_BYTES,
        "larger than {} MiB, the most a scene file may be",
        MAX_SCENE_BYTES >> 20
    );
    Ok(String::from_utf8(bytes)?)
}
