//! `--engine k8s` writes an Indexed Job manifest. No Kubernetes cluster can run here, so the
//! manifest is checked for its structure (parsed, every field that makes it an indexed sweep
//! looked at), and the command its pods run is run here, as a pod would run it with its
//! completion index, against the folder the volume would hold.

mod common;
mod sweep_common;

use serde_json::Value;
use sweep_common::*;

#[test]
fn the_manifest_is_an_indexed_job_whose_pods_run_one_run_each() {
    let dir = tmp("k8s");
    let out = dir.join("smoke-out");
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
    let m: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("k8s/job.json")).unwrap()).unwrap();
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
