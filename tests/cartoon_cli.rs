//! The cartoon techniques from the command line: each renders and profiles, and bad cartoon
//! options get a one-line error naming the option.

mod common;

use std::process::{Command, Output};

fn nostencil(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_nostencil")).args(args).output().expect("run nostencil")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

#[test]
fn every_cartoon_technique_and_method_renders_and_profiles() {
    let dir = common::scratch_dir("cartoon-cli");
    let cases: [&[&str]; 6] = [
        &["--scene", "outline", "--technique", "outline", "--select", "box,sphere"],
        &["--scene", "outline", "--technique", "outline", "--stencil", "reference"],
        &["--scene", "outline", "--technique", "silhouette", "--line-width", "3", "--crease-angle", "30"],
        &["--scene", "duck", "--technique", "toon", "--silhouette", "shader"],
        &["--scene", "default", "--technique", "toon", "--silhouette", "hull"],
        &["--scene", "duck", "--technique", "silhouette", "--silhouette", "edges"],
    ];
    for (i, extra) in cases.iter().enumerate() {
        let out = dir.join(format!("{i}.png"));
        let mut args = vec!["render", "--size", "96x64", "--validation", "--out"];
        args.push(out.to_str().expect("utf-8 path"));
        args.extend_from_slice(extra);
        let output = nostencil(&args);
        assert!(output.status.success(), "{extra:?}: {}", stderr(&output));
        assert!(!stderr(&output).contains("validation"), "{extra:?}: {}", stderr(&output));
        let image = image::open(&out).expect("a PNG").to_rgb8();
        assert_eq!(image.dimensions(), (96, 64));

        let mut args = vec!["profile", "--size", "96x64", "--format", "json"];
        args.extend_from_slice(extra);
        let output = nostencil(&args);
        assert!(output.status.success(), "{extra:?}: {}", stderr(&output));
        let json: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
        assert!(json["passes"].as_array().is_some_and(|p| !p.is_empty()), "{extra:?}");
    }
}

#[test]
fn bad_cartoon_options_are_one_line_errors() {
    for (args, mentions) in [
        (&["--technique", "toon", "--silhouette", "sketch"][..], "--silhouette"),
        (&["--technique", "outline", "--select", "teapot"][..], "teapot"),
        (&["--technique", "silhouette", "--line-width", "0"][..], "--line-width"),
        (&["--technique", "silhouette", "--crease-angle", "500"][..], "--crease-angle"),
    ] {
        let mut all = vec!["profile", "--size", "32x32", "--scene", "outline"];
        all.extend_from_slice(args);
        let output = nostencil(&all);
        let err = stderr(&output);
        assert!(!output.status.success(), "{args:?} succeeded");
        assert!(!err.contains("panicked"), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(mentions), "'{mentions}' not in {err}");
    }
}
