//! Unit tests of `output`.
use super::*;
use crate::aggregate::Aggregator;
use crate::fixtures::row;
use crate::report::{CounterSupport, FrameRows, NotMeasured, RunEnd, FILLRATE_SCHEMA};

#[test]
fn an_atomic_write_replaces_the_file_whole_and_a_failed_one_leaves_nothing() {
    let dir = std::env::temp_dir().join(format!("fillrate-report-write-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("report.json");
    write_atomically(&file, "first").unwrap();
    write_atomically(&file, "second").unwrap();
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "second");
    // The rename fails onto a folder that is not empty; its temporary file goes with it.
    let occupied = dir.join("occupied");
    std::fs::create_dir_all(occupied.join("inside")).unwrap();
    assert!(write_atomically(&occupied, "text").is_err());
    let names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|n| !n.ends_with(".partial")), "{names:?}");
    std::fs::remove_dir_all(&dir).unwrap();
}

fn report() -> FillrateReport {
    let mut passes = vec![row(10, 100, Some(1e6)), row(20, 7, None)];
    passes[1].index = 1;
    passes[0].label = Some("shadow, \"main\"".into());
    passes.push(RenderPassRow {
        per_draw: Vec::new(),
        sections: Vec::new(),
        index: 2,
        counters: None,
        not_measured: Some("secondary command buffer".into()),
        ..row(20, 0, None)
    });
    let mut aggregate = Aggregator::default();
    aggregate.add_frame(&passes);
    FillrateReport {
        schema: FILLRATE_SCHEMA.into(),
        application: "app".into(),
        device: "gpu".into(),
        counters: CounterSupport { pipeline_statistics: true, occlusion_precise: true, timestamps: false },
        frames_measured: 1,
        not_measured: vec![NotMeasured { what: "secondary command buffer".into(), count: 1 }],
        frames: vec![FrameRows { index: 0, render_passes: passes, work: Vec::new() }],
        aggregate: aggregate.rows(),
        work_aggregate: Vec::new(),
        run: Some(RunEnd {
            how: "crashed".into(),
            detail: "crashed with SIGSEGV after 1 measured frame".into(),
            partial: true,
        }),
        hidden_extensions: Vec::new(),
        tiler_check: None,
    }
}

#[test]
fn json_round_trips_through_the_same_types() {
    let report = report();
    let text = render(&report, OutputFormat::Json);
    assert_eq!(FillrateReport::from_json(&text), Ok(report));
    let wrong = text.replace(FILLRATE_SCHEMA, "nostencil-fillrate/0");
    assert!(FillrateReport::from_json(&wrong).is_err_and(|e| e.contains("nostencil-fillrate/0")));
}

#[test]
fn csv_has_one_line_per_pass_then_mean_min_max_with_quoted_fields() {
    let text = render(&report(), OutputFormat::Csv);
    let lines: Vec<&str> = text.lines().collect();
    let columns = CSV_HEADER.split(',').count();
    // Header, 3 passes, 2 aggregated passes x 3 lines.
    assert_eq!(lines.len(), 1 + 3 + 6);
    assert!(lines[1].starts_with("0,0,\"shadow, \"\"main\"\"\",vkCmdBeginRenderPass,0,0,10,10,1,"));
    assert!(lines[1].contains(",2,6,2,200,2,100,1,1,0,0,"), "{}", lines[1]);
    assert!(lines[3].ends_with(",secondary command buffer,,render_pass,,,,,"), "{}", lines[3]);
    assert!(lines[4].starts_with("mean,0,"));
    assert!(lines[5].starts_with("min,0,") && lines[6].starts_with("max,0,"));
    // Every line has the header's columns (lines with a quoted comma aside).
    for line in lines.iter().filter(|l| !l.contains('"')) {
        assert_eq!(line.split(',').count(), columns, "{line}");
    }
}

#[test]
fn table_lists_the_last_frame_the_aggregate_and_what_was_not_measured() {
    let text = render(&report(), OutputFormat::Table);
    assert!(text.starts_with("app | gpu | 1 frame(s) measured | pipeline statistics yes"));
    assert!(text.contains("run: crashed with SIGSEGV after 1 measured frame (partial report"));
    assert!(text.contains("#0 shadow, \"main\""));
    assert!(text.contains("not measured: secondary command buffer"));
    assert!(text.contains("aggregate over 1 frame(s)"));
    assert!(text.contains("1 x secondary command buffer"));
}

#[test]
fn sections_are_rows_under_their_pass_in_every_format_and_the_aggregate() {
    let mut report = report();
    let pass = &mut report.frames[0].render_passes[0];
    pass.label = Some("frame".into());
    let section = |label: Option<&str>, samples| SectionRow {
        label: label.map(str::to_owned),
        counters: row(10, samples, None).counters,
        not_measured: None,
        per_draw: Vec::new(),
    };
    pass.sections = vec![section(Some("volumes (alpha, z-pass)"), 60), section(None, 40)];
    let mut aggregate = Aggregator::default();
    aggregate.add_frame(&report.frames[0].render_passes);
    report.aggregate = aggregate.rows();
    assert_eq!(report.aggregate[0].sections.len(), 2);
    assert_eq!(report.aggregate[0].sections[0].min.samples_passed, 60);

    let table = render(&report, OutputFormat::Table);
    assert!(table.contains("#0 frame / volumes (alpha, z-pass)"), "{table}");
    assert!(table.contains("#0 frame / (unlabelled)"), "{table}");
    let csv = render(&report, OutputFormat::Csv);
    let sections: Vec<&str> =
        csv.lines().filter(|l| l.ends_with(",\"volumes (alpha, z-pass)\",render_pass,,,,,")).collect();
    // The frame's line and the aggregate's mean, min and max.
    assert_eq!(sections.len(), 4, "{csv}");
    assert!(sections[0].starts_with("0,0,frame,"), "{}", sections[0]);
    let json = render(&report, OutputFormat::Json);
    assert_eq!(FillrateReport::from_json(&json), Ok(report));
}

#[test]
fn work_rows_follow_the_passes_in_the_table_and_csv_and_count_in_the_frames_bytes() {
    use crate::report::{WorkCounters, WorkRow};
    use crate::work_aggregate::WorkAggregator;
    let mut report = report();
    let counters = |invocations, read, written| WorkCounters {
        commands: 2,
        workgroups: Some(12),
        compute_invocations: invocations,
        bytes_read: read,
        bytes_written: written,
        gpu_ms: Some(0.5),
    };
    let row = |index, kind: &str, api: &str, c| WorkRow {
        index,
        kind: kind.into(),
        api: api.into(),
        label: Some("blur".into()),
        counters: Some(c),
        not_measured: None,
        note: None,
    };
    report.frames[0].work = vec![
        row(0, "compute", "vkCmdDispatch", counters(Some(384), 0, 0)),
        WorkRow {
            note: Some("full-frame blit into a swapchain image (8x8)".into()),
            ..row(1, "transfer", "vkCmdBlitImage", counters(None, 256, 1024))
        },
    ];
    let mut aggregate = WorkAggregator::default();
    aggregate.add_frame(&report.frames[0].work);
    report.work_aggregate = aggregate.rows();

    let table = render(&report, OutputFormat::Table);
    assert!(table.contains("compute and transfers outside render passes"), "{table}");
    assert!(table.contains("#0 blur") && table.contains("384") && table.contains("vkCmdBlitImage"), "{table}");
    assert!(table.contains("#1 blur: full-frame blit into a swapchain image (8x8)"), "{table}");
    assert!(table.contains("transfers' 1280 B included"), "{table}");
    assert!(table.contains("aggregate of the work outside render passes"), "{table}");
    let csv = render(&report, OutputFormat::Csv);
    let columns = CSV_HEADER.split(',').count();
    let work: Vec<&str> =
        csv.lines().filter(|l| l.contains(",vkCmdDispatch,") || l.contains(",vkCmdBlitImage,")).collect();
    // The frame's two rows, and mean, min and max of each.
    assert_eq!(work.len(), 2 + 6, "{csv}");
    for line in &work {
        assert_eq!(line.split(',').count(), columns, "{line}");
    }
    assert!(
        work[0].starts_with("0,0,blur,vkCmdDispatch,") && work[0].ends_with(",compute,2,12,384,0,0"),
        "{}",
        work[0]
    );
    assert!(work[1].ends_with(",1280,1280,,,transfer,2,12,,256,1024"), "{}", work[1]);
    let json = render(&report, OutputFormat::Json);
    assert_eq!(FillrateReport::from_json(&json), Ok(report));
}

#[test]
fn atomic_write_leaves_only_the_target() {
    let dir = std::env::temp_dir().join(format!("nostencil-fillrate-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("out.json");
    write_atomically(&path, "one").expect("write");
    write_atomically(&path, "two").expect("rewrite");
    assert_eq!(std::fs::read_to_string(&path).expect("read"), "two");
    assert_eq!(std::fs::read_dir(&dir).expect("list").count(), 1);
    let _ = std::fs::remove_dir_all(&dir);
}
