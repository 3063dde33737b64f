//! `--engine k8s` writes an Indexed Job manifest. No Kubernetes cluster can run here, so the
//! manifest is validated against the strict batch/v1 Job schema of Kubernetes v1.37
//! (vendored in `tests/k8s-schema`, see its README: no field the API does not have, every
//! field of its type), checked for its structure (every field that makes it an indexed sweep
//! looked at), and the command its pods run is run here, as a pod would run it with its
//! completion index, against the folder the volume would hold.

mod common;
mod sweep_common;

use serde_json::{Value, json};
use std::path::Path;
use sweep_common::*;

/// The vendored strict batch/v1 Job schema, compiled.
fn job_schema() -> jsonschema::Validator {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/k8s-schema/job-batch-v1.json");
    let schema: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    jsonschema::validator_for(&schema).expect("the Job schema compiles")
}

/// Where and why `manifest` breaks the Job schema (empty: it is a valid Job).
fn schema_errors(schema: &jsonschema::Validator, manifest: &Value) -> Vec<String> {
    schema
        .iter_errors(manifest)
        .map(|e| format!("{}: {e}", e.instance_path()))
        .collect()
}

/// Writes the smoke sweep's manifest into `out` (`--max-parallel 3`, an image and a claim
/// named) and returns it.
fn write_manifest(out: &Path) -> Value {
    let o = shoal(&[
        "sweep",
        smoke().to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--engine",
        "k8s",
        "--image",
        "registry.example.org/shoal:0.1",
        "--pvc",
        "sweeps-rwx",
        "--max-parallel",
        "3",
    ]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("kubectl apply -f"),
        "{}",
        text(&o)
    );
    serde_json::from_str(&std::fs::read_to_string(out.join("k8s/job.json")).unwrap()).unwrap()
}

#[test]
fn the_manifest_is_an_indexed_job_whose_pods_run_one_run_each() {
    let dir = tmp("k8s");
    let out = dir.join("smoke-out");
    let m = write_manifest(&out);
    assert_eq!(schema_errors(&job_schema(), &m), Vec::<String>::new());
    assert_eq!(m["apiVersion"], "batch/v1");
    assert_eq!(m["kind"], "Job");
    let name = m["metadata"]["name"].as_str().unwrap();
    assert!(
        name.len() <= 63
            && name.starts_with("shoal-smoke-")
            && name
                .chars()
                .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'),
        "not a DNS-1123 label: {name}"
    );
    let spec = &m["spec"];
    assert_eq!(spec["completionMode"], "Indexed");
    assert_eq!(spec["completions"], 8);
    assert_eq!(spec["parallelism"], 3);
    assert_eq!(spec["backoffLimitPerIndex"], 0);
    let pod = &spec["template"]["spec"];
    assert_eq!(pod["restartPolicy"], "Never");
    let containers = pod["containers"].as_array().unwrap();
    assert_eq!(containers.len(), 1);
    let c = &containers[0];
    assert_eq!(c["image"], "registry.example.org/shoal:0.1");
    let cmd: Vec<&str> = c["command"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(
        cmd[..6],
        [
            "shoal",
            "sweep",
            "run-one",
            "/sweeps/smoke-out",
            "--index",
            "$(JOB_COMPLETION_INDEX)"
        ]
    );
    // The index comes from the pod's completion-index annotation.
    let env = c["env"].as_array().unwrap();
    let idx = env
        .iter()
        .find(|e| e["name"] == "JOB_COMPLETION_INDEX")
        .expect("JOB_COMPLETION_INDEX in env");
    assert_eq!(
        idx["valueFrom"]["fieldRef"]["fieldPath"],
        "metadata.annotations['batch.kubernetes.io/job-completion-index']"
    );
    // The output folder is on the mounted claim.
    let mount = &c["volumeMounts"][0];
    assert_eq!(mount["mountPath"], "/sweeps");
    let vol = pod["volumes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|v| v["name"] == mount["name"])
        .expect("the mounted volume");
    assert_eq!(vol["persistentVolumeClaim"]["claimName"], "sweeps-rwx");
    // Nothing ran here, but the folder holds what the pods need.
    let plan: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("plan.json")).unwrap()).unwrap();
    let runs = plan["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 8);
    for r in runs {
        let rdir = out.join("runs").join(r["run"].as_str().unwrap());
        assert!(rdir.join("world.toml").exists());
        assert!(!rdir.join("result.json").exists());
    }
    // A pod's command, with the volume's mount point where this folder is and index 6.
    let args: Vec<String> = cmd[1..]
        .iter()
        .map(|a| {
            a.replace("/sweeps", dir.to_str().unwrap())
                .replace("$(JOB_COMPLETION_INDEX)", "6")
        })
        .collect();
    let o = shoal(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", text(&o));
    let o = shoal(&["sweep", "collect", out.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    let (_, rows) = table(&out);
    let status: Vec<&str> = rows.iter().map(|r| r["status"].as_str()).collect();
    assert_eq!(
        status,
        [
            "missing", "missing", "missing", "missing", "missing", "missing", "ok", "missing"
        ]
    );
    assert_eq!(rows[6]["vehicles.0.count"], "4");
    assert_eq!(rows[6]["water.attenuation"], "turbid_harbour");
    // The same pod again (a re-applied Job) does nothing: the run is complete.
    let o = shoal(&args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        String::from_utf8_lossy(&o.stdout).contains("already complete"),
        "{}",
        text(&o)
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A way to break a manifest, and where (a JSON pointer) the schema must then object.
type Breakage = (&'static str, fn(&mut Value));

/// The schema check sees what is wrong: the manifest with a misspelt field, or a field of
/// the wrong type, at any depth, breaks the schema there.
#[test]
fn the_schema_check_catches_a_misspelt_field_and_a_wrong_type() {
    let dir = tmp("k8s-schema");
    let m = write_manifest(&dir.join("smoke-out"));
    let schema = job_schema();
    assert_eq!(schema_errors(&schema, &m), Vec::<String>::new());
    let broken: [Breakage; 5] = [
        ("/spec", |m| {
            let spec = m["spec"].as_object_mut().unwrap();
            let mode = spec.remove("completionMode").unwrap();
            spec.insert("completionMod".into(), mode);
        }),
        ("/spec/completions", |m| {
            m["spec"]["completions"] = json!("8")
        }),
        ("/spec/template/spec/containers/0", |m| {
            let c = &mut m["spec"]["template"]["spec"]["containers"][0];
            let mounts = c.as_object_mut().unwrap().remove("volumeMounts").unwrap();
            c["volumeMount"] = mounts;
        }),
        ("/spec/template/spec/containers/0/command/0", |m| {
            m["spec"]["template"]["spec"]["containers"][0]["command"][0] = json!(1)
        }),
        ("/spec/template/spec/restartPolicy", |m| {
            m["spec"]["template"]["spec"]["restartPolicy"] = json!(["Never"])
        }),
    ];
    for (at, breaks) in broken {
        let mut bad = m.clone();
        breaks(&mut bad);
        let errors = schema_errors(&schema, &bad);
        assert!(
            errors.iter().any(|e| e.starts_with(&format!("{at}: "))),
            "nothing found at {at}: {errors:?}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}
