//! Compiles every GLSL stage in `shaders/` to SPIR-V with shaderc and generates
//! `$OUT_DIR/shaders.rs`, a table from shader file name to its SPIR-V bytes, and a constant
//! naming each shader (`crate::shaders::LIT_VERT`).
//! A compile error stops the build with the file, line and message that glslang gave.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

const STAGES: [(&str, shaderc::ShaderKind); 3] = [
    ("vert", shaderc::ShaderKind::Vertex),
    ("frag", shaderc::ShaderKind::Fragment),
    ("comp", shaderc::ShaderKind::Compute),
];

fn main() {
    let manifest = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets this"));
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets this"));
    let shader_dir = manifest.join("shaders");
    println!("cargo:rerun-if-changed={}", shader_dir.display());

    let mut sources: Vec<PathBuf> = std::fs::read_dir(&shader_dir)
        .unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", shader_dir.display())))
        .filter_map(|entry| entry.ok().map(|e| e.path()))
        .collect();
    sources.sort();

    let compiler = shaderc::Compiler::new()
        .unwrap_or_else(|| fail("shaderc could not create a compiler (see tools/setup-debian.sh)"));
    let mut table = String::from("/// (file name, SPIR-V) for every shader in `shaders/`.\n");
    table.push_str("pub static SHADERS: &[(&str, &[u8])] = &[\n");
    // One constant per shader file: code names a shader that exists, or does not build.
    let mut names = String::new();

    for path in &sources {
        println!("cargo:rerun-if-changed={}", path.display());
        let Some(ext) = path.extension().and_then(|e| e.to_str()) else { continue };
        let Some(&(_, kind)) = STAGES.iter().find(|(e, _)| *e == ext) else { continue };
        let file_name = path.file_name().and_then(|n| n.to_str()).unwrap_or_default().to_owned();
        let source =
            std::fs::read_to_string(path).unwrap_or_else(|e| fail(&format!("cannot read {}: {e}", path.display())));

        let mut variants = vec![(file_name.clone(), None)];
        // A vertex shader marked as having a skinned twin is also compiled with SKINNED
        // defined (`lit.vert` -> `lit.skinned.vert`): the same stage skinning its vertices on
        // the GPU (`shaders/object_vertex.glsl`).
        if kind == shaderc::ShaderKind::Vertex && source.lines().any(|l| l.trim() == SKINNED_TWIN_MARK) {
            variants.push((file_name.replace(".vert", ".skinned.vert"), Some("SKINNED")));
        }
        for (name, define) in variants {
            compile_variant(
                &compiler,
                &shader_dir,
                &out_dir,
                (path, &source, kind),
                (&name, define),
                (&mut table, &mut names),
            );
        }
    }
    table.push_str("];\n");
    table.push_str(&names);
    let table_path = out_dir.join("shaders.rs");
    std::fs::write(&table_path, table).unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", table_path.display())));
    if std::env::var_os("CARGO_FEATURE_EMBEDDED_LAYER").is_some() {
        build_layer_into(&manifest, &out_dir);
    }
}

/// The line that gives a vertex shader a skinned twin.
const SKINNED_TWIN_MARK: &str = "// twin: skinned";

/// Compiles one variant of a stage (`define`d when it is a twin), writes its SPIR-V, and adds it
/// to the table and the names; a vertex stage also gets its overdraw counter.
fn compile_variant(
    compiler: &shaderc::Compiler,
    shader_dir: &Path,
    out_dir: &Path,
    (path, source, kind): (&Path, &str, shaderc::ShaderKind),
    (file_name, define): (&str, Option<&str>),
    (table, names): (&mut String, &mut String),
) {
    let spirv = compile(compiler, shader_dir, path, source, kind, define);
    let spv_path = out_dir.join(format!("{file_name}.spv"));
    std::fs::write(&spv_path, spirv.as_binary_u8())
        .unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", spv_path.display())));
    let _ = writeln!(table, "    ({file_name:?}, include_bytes!({:?})),", spv_path.display().to_string());
    let _ = writeln!(
        names,
        // Every file gets its constant, named in code or not: a skinned twin is reached through
        // `Shader::skinned_twin`, and some files only by the tests' own Vulkan programs.
        "/// `shaders/{file_name}`.\n#[allow(dead_code)]\npub const {}: Shader = Shader({file_name:?});",
        constant_name(file_name)
    );

    if kind == shaderc::ShaderKind::Vertex {
        // The overdraw heat map swaps every fragment shader for a counter; one counter per
        // vertex shader, declaring that stage's outputs as inputs so the interfaces match.
        let counter_name = format!("{file_name}.count.frag");
        let counter_source = overdraw_counter_source(shader_dir, source);
        let counter = compile(
            compiler,
            shader_dir,
            &shader_dir.join(&counter_name),
            &counter_source,
            shaderc::ShaderKind::Fragment,
            None,
        );
        let counter_path = out_dir.join(format!("{counter_name}.spv"));
        std::fs::write(&counter_path, counter.as_binary_u8())
            .unwrap_or_else(|e| fail(&format!("cannot write {}: {e}", counter_path.display())));
        let _ = writeln!(table, "    ({counter_name:?}, include_bytes!({:?})),", counter_path.display().to_string());
    }
}

/// With the `embedded-layer` feature: the fill-rate layer's library, built from its crate in this
/// workspace (release, in a target folder of its own under OUT_DIR) and copied to
/// `$OUT_DIR/libnostencil_fillrate.so`, which `cli/install.rs` includes. `cargo install` installs
/// only executables, so this is how an installed `nostencil` still has a layer to install.
fn build_layer_into(manifest: &Path, out_dir: &Path) {
    const LIBRARY: &str = "libnostencil_fillrate.so";
    let layer_crate = manifest.join("crates/fillrate-layer");
    println!("cargo:rerun-if-changed={}", layer_crate.display());
    println!("cargo:rerun-if-changed={}", manifest.join("crates/fillrate-report").display());
    println!("cargo:rerun-if-changed={}", manifest.join("crates/tiler").display());
    let target_dir = out_dir.join("layer-build");
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let status = std::process::Command::new(cargo)
        .args(["build", "--release", "--lib", "--package", "nostencil-fillrate-layer", "--manifest-path"])
        .arg(manifest.join("Cargo.toml"))
        .arg("--target-dir")
        .arg(&target_dir)
        .env_remove("CARGO_TARGET_DIR")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .status()
        .unwrap_or_else(|e| fail(&format!("cannot run cargo to build the layer: {e}")));
    if !status.success() {
        fail(&format!("building the fill-rate layer for `embedded-layer` failed ({status})"));
    }
    let built = target_dir.join("release").join(LIBRARY);
    std::fs::copy(&built, out_dir.join(LIBRARY))
        .unwrap_or_else(|e| fail(&format!("cannot copy {}: {e}", built.display())));
}

/// The constant a shader file is named by: `shadow_volume.vert` -> `SHADOW_VOLUME_VERT`.
fn constant_name(file_name: &str) -> String {
    file_name.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_uppercase() } else { '_' }).collect()
}

/// A fragment shader that adds 1/255 to alpha and declares, as unused inputs, every
/// `layout(location = N) [flat] out TYPE NAME;` the vertex shader (or its includes) writes.
fn overdraw_counter_source(shader_dir: &Path, vertex_source: &str) -> String {
    let mut inputs = String::new();
    let mut lines: Vec<String> = Vec::new();
    for line in vertex_source.lines() {
        if let Some(include) = line.trim().strip_prefix("#include") {
            let name = include.trim().trim_matches('"');
            lines.extend(std::fs::read_to_string(shader_dir.join(name)).unwrap_or_default().lines().map(String::from));
        } else {
            lines.push(line.to_owned());
        }
    }
    for line in &lines {
        let line = line.trim();
        if !line.starts_with("layout") || !line.contains(" out ") || line.contains("gl_") {
            continue;
        }
        let Some((layout, rest)) = line.split_once(')') else { continue };
        let rest = rest.trim().trim_end_matches(';');
        let mut words: Vec<&str> = rest.split_whitespace().collect();
        let flat = words.first() == Some(&"flat");
        words.retain(|w| *w != "flat" && *w != "out" && *w != "smooth" && *w != "noperspective");
        if let [ty, name] = words[..] {
            let integer =
                ty.starts_with("int") || ty.starts_with("uint") || ty.starts_with("ivec") || ty.starts_with("uvec");
            let qualifier = if flat || integer { "flat " } else { "" };
            let _ = writeln!(inputs, "{layout}) {qualifier}in {ty} {name};");
        }
    }
    format!(
        "#version 450\n{inputs}layout(location = 0) out vec4 out_colour;\nvoid main() {{\n    out_colour = vec4(0.0, 0.0, 0.0, 1.0 / 255.0);\n}}\n"
    )
}

fn compile(
    compiler: &shaderc::Compiler,
    shader_dir: &Path,
    path: &Path,
    source: &str,
    kind: shaderc::ShaderKind,
    define: Option<&str>,
) -> shaderc::CompilationArtifact {
    let mut options =
        shaderc::CompileOptions::new().unwrap_or_else(|| fail("shaderc could not create compile options"));
    // Vulkan 1.0 / SPIR-V 1.0: what every mobile-class device accepts.
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_0 as u32);
    options.set_warnings_as_errors();
    if let Some(define) = define {
        options.add_macro_definition(define, None);
    }
    let include_dir = shader_dir.to_path_buf();
    options.set_include_callback(move |name, _kind, _from, _depth| {
        let include_path = include_dir.join(name);
        println!("cargo:rerun-if-changed={}", include_path.display());
        std::fs::read_to_string(&include_path)
            .map(|content| shaderc::ResolvedInclude { resolved_name: include_path.display().to_string(), content })
            .map_err(|e| format!("cannot include {}: {e}", include_path.display()))
    });
    let display_name = path.display().to_string();
    compiler
        .compile_into_spirv(source, kind, &display_name, "main", Some(&options))
        // glslang's message already reads "shaders/x.frag:12: error: ...".
        .unwrap_or_else(|e| fail(&format!("shader compilation failed:\n{e}")))
}

fn fail(message: &str) -> ! {
    eprintln!("error: {message}");
    std::process::exit(1);
}
