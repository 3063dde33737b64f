//! The Kubernetes engine: an Indexed Job manifest (`DIR/k8s/job.json`) that runs the sweep as
//! one pod per run, never applied by shoal itself (`kubectl apply -f DIR/k8s/job.json`).
//!
//! The Job has `completionMode: Indexed` and one completion per run; each pod runs
//! `shoal sweep run-one /sweeps/<path> --index $(JOB_COMPLETION_INDEX)`, the index taken from
//! the pod's `batch.kubernetes.io/job-completion-index` annotation through the downward API.
//! The output folder lives on a PersistentVolumeClaim (ReadWriteMany, so that all pods and
//! the machine that collects share it) mounted at `/sweeps`, at `<path>` inside the volume.
//! A pod whose run is already complete ends at once, so applying the Job again after a partial
//! sweep redoes only what is missing (and, with `--retry-failed`, what failed).
//! `backoffLimitPerIndex: 0` (Kubernetes ≥ 1.29) keeps a failed run from being retried and
//! from stopping the others. JSON is YAML, so kubectl reads the file as it is.

use super::plan::Plan;
use serde_json::{Value, json};
use shoal_output::files::write_whole;
use std::path::{Path, PathBuf};

/// Largest number of completions of an Indexed Job.
pub const MAX_COMPLETIONS: usize = 100_000;
/// Where the volume is mounted in each pod.
pub const MOUNT: &str = "/sweeps";

/// Options of the Kubernetes engine.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct K8sArgs {
    /// Container image with the `shoal` binary on its PATH (the same version that expanded
    /// the sweep).
    #[arg(long, default_value = "shoal:latest")]
    pub image: String,
    /// PersistentVolumeClaim (ReadWriteMany) that holds the output folder.
    #[arg(long, default_value = "shoal-sweeps")]
    pub pvc: String,
    /// Where the output folder is inside that volume [default: the folder's own name].
    #[arg(long)]
    pub pvc_path: Option<String>,
}

/// A DNS-1123 label for the Job's name: `shoal-<sweep>-<plan>`, at most 63 characters.
fn job_name(plan: &Plan) -> String {
    let mut slug: String = plan
        .name
        .to_lowercase()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '-' })
        .collect();
    slug = slug
        .split('-')
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join("-");
    slug.truncate(40);
    let slug = slug.trim_end_matches('-');
    let id = plan.id();
    if slug.is_empty() {
        format!("shoal-{}", &id[..8])
    } else {
        format!("shoal-{slug}-{}", &id[..8])
    }
}

/// The Indexed Job for `plan`, its output folder at `path` inside the volume.
pub fn manifest(
    plan: &Plan,
    path: &str,
    parallelism: Option<u32>,
    retry_failed: bool,
    o: &K8sArgs,
) -> Value {
    let dir = format!("{MOUNT}/{}", path.trim_matches('/'));
    let mut command = vec![
        json!("shoal"),
        json!("sweep"),
        json!("run-one"),
        json!(dir),
        json!("--index"),
        json!("$(JOB_COMPLETION_INDEX)"),
        json!("--plan"),
        json!(plan.id()),
    ];
    if retry_failed {
        command.push(json!("--retry-failed"));
    }
    let n = plan.runs.len();
    json!({
        "apiVersion": "batch/v1",
        "kind": "Job",
        "metadata": {
            "name": job_name(plan),
            "labels": {"app.kubernetes.io/name": "shoal-sweep", "shoal/plan": plan.id()}
        },
        "spec": {
            "completionMode": "Indexed",
            "completions": n,
            "parallelism": parallelism.map_or(n, |k| (k as usize).min(n)),
            "backoffLimitPerIndex": 0,
            "template": {
                "metadata": {"labels": {"app.kubernetes.io/name": "shoal-sweep"}},
                "spec": {
                    "restartPolicy": "Never",
                    "containers": [{
                        "name": "run",
                        "image": o.image,
                        "command": command,
                        "env": [{
                            "name": "JOB_COMPLETION_INDEX",
                            "valueFrom": {"fieldRef": {
                                "fieldPath": "metadata.annotations['batch.kubernetes.io/job-completion-index']"
                            }}
                        }],
                        "resources": {
                            "requests": {"cpu": "1"},
                            "limits": {"cpu": "1"}
                        },
                        "volumeMounts": [{"name": "sweeps", "mountPath": MOUNT}]
                    }],
                    "volumes": [{
                        "name": "sweeps",
                        "persistentVolumeClaim": {"claimName": o.pvc}
                    }]
                }
            }
        }
    })
}

/// Writes `DIR/k8s/job.json`; returns its path.
pub fn write(
    dir: &Path,
    plan: &Plan,
    parallelism: Option<u32>,
    retry_failed: bool,
    o: &K8sArgs,
) -> Result<PathBuf, crate::exit::Failure> {
    if plan.runs.len() > MAX_COMPLETIONS {
        return Err(crate::exit::Failure::Input(format!(
            "the sweep has {} runs; an Indexed Job has at most {MAX_COMPLETIONS} completions",
            plan.runs.len()
        )));
    }
    let path = match &o.pvc_path {
        Some(p) => p.clone(),
        None => dir
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default(),
    };
    if path.trim_matches('/').is_empty() || path.split('/').any(|s| s == "..") {
        return Err(crate::exit::Failure::Input(format!(
            "--pvc-path `{path}`: a folder inside the volume (no `..`)"
        )));
    }
    let kdir = dir.join("k8s");
    std::fs::create_dir_all(&kdir).map_err(|e| {
        crate::exit::Failure::Other(anyhow::anyhow!(
            "cannot create the folder {}: {e}",
            kdir.display()
        ))
    })?;
    let m = manifest(plan, &path, parallelism, retry_failed, o);
    let text =
        serde_json::to_string_pretty(&m).map_err(|e| crate::exit::Failure::Other(e.into()))?;
    write_whole(&kdir.join("job.json"), (text + "\n").as_bytes())
        .map_err(|e| crate::exit::Failure::Other(e.into()))
}
