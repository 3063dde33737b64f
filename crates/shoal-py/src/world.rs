//! `shoal.World`: a whole world in the Python process. It is loaded and built exactly as
//! `shoal run` loads and builds it (the same file, the same seed → the same state digest,
//! [`World::digest`]), stepped with the GIL released, commanded and observed through numpy
//! arrays over all vehicles at once.
//!
//! One `step()` is one control period by default (`tick_steps` physics steps): commands are
//! applied first, so they act at the next control tick like an external agent's, and the
//! sensor readings observed afterwards are the ones the next tick's controller sees.

use crate::args::{self, FloatRows, bad};
use crate::errors::{SimulationError, command_error};
use crate::observe;
use crate::source::{self, Source};
use numpy::IntoPyArray;
use numpy::ndarray::Array2;
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use shoal_sim::batch::{ActuatorOrder, Arrivals, BatchShape, Quantity, SetpointOrder};
use shoal_sim::orders::force_limit;
use shoal_sim::sim::{Sim, SimOptions};
use shoal_world::desc::WorldDesc;

/// Keys of a setpoint command.
const SETPOINT_KEYS: [&str; 5] = ["mode", "depth", "yaw", "surge", "sway"];
/// Keys of a raw actuator command.
const RAW_KEYS: [&str; 3] = ["thrusters", "tilts", "pump"];

/// A shoal world in this process: `World(world=None, seed=None, threads=None)`.
///
/// `world` is a world file's path (str or path-like) or the TOML text of a world (a str
/// containing a newline or `=`); without it, the embedded default world of `shoal run`.
/// `seed` overrides the file's seed; `threads` is the number of working threads for
/// per-vehicle loops (default: every core, as `shoal run`; results are the same for any
/// number). Units are SI, angles in radians, depth positive down (north-east-down frame).
#[pyclass(module = "shoal._shoal")]
pub struct World {
    /// Where the world came from (read again by `reset` with another seed).
    source: Source,
    desc: WorldDesc,
    sim: Sim,
    threads: usize,
    shape: BatchShape,
    tick: u64,
    max_payload: usize,
    received: Arrivals,
    /// Whether `send` has warned about frames of several vehicles starting together.
    warned_sync: bool,
}

/// Builds the world's simulation (no trajectory recording: the arrays are the output).
fn build(py: Python<'_>, desc: &WorldDesc, threads: usize) -> Sim {
    py.detach(|| {
        Sim::new(
            desc,
            SimOptions {
                threads,
                record: false,
            },
        )
    })
}

impl World {
    /// Raises the simulation fault, if any.
    fn check_fault(&self) -> PyResult<()> {
        match self.sim.fault() {
            Some(f) => Err(SimulationError::new_err(format!(
                "the world cannot continue (reset it): at t = {} s {f}",
                f.state.time
            ))),
            None => Ok(()),
        }
    }

    /// Advances `steps` physics steps with the GIL released, keeping the frames delivered
    /// when `keep_frames` (else only taking agent-driven vehicles' frames, which nobody else
    /// would).
    fn advance(&mut self, py: Python<'_>, steps: u64, keep_frames: bool) -> PyResult<()> {
        self.check_fault()?;
        self.received.clear();
        // Agent-driven vehicles' inboxes are emptied here (no agent host runs in-process).
        let agents = !self.desc.agents.names.is_empty();
        let collect = self.shape.modems > 0 && (keep_frames || agents);
        let (sim, received) = (&mut self.sim, &mut self.received);
        py.detach(|| {
            for _ in 0..steps {
                if sim.fault().is_some() {
                    break;
                }
                let t0 = sim.time();
                sim.step();
                if collect {
                    sim.collect_received(t0, keep_frames.then_some(&mut *received), agents);
                }
            }
        });
        self.check_fault()
    }

    /// Quantity `q` of every vehicle.
    fn quantity<'py>(&mut self, py: Python<'py>, q: Quantity) -> PyResult<Bound<'py, PyAny>> {
        observe::quantity(py, &mut self.sim, &self.shape, q)
    }

    /// Applies a command dict (see `step`).
    fn apply(&mut self, py: Python<'_>, commands: &Bound<'_, PyDict>, clip: bool) -> PyResult<()> {
        let mut sp = false;
        let mut raw = false;
        for k in commands.keys() {
            let k: String = k.extract()?;
            if SETPOINT_KEYS.contains(&k.as_str()) {
                sp = true;
            } else if RAW_KEYS.contains(&k.as_str()) {
                raw = true;
            } else if k != "vehicles" {
                return Err(bad(
                    "commands",
                    format!(
                        "unknown key `{k}`: use setpoints ({}) or raw actuators ({}), and \
                         optionally `vehicles`",
                        SETPOINT_KEYS.join(", "),
                        RAW_KEYS.join(", ")
                    ),
                ));
            }
        }
        if sp && raw {
            return Err(bad(
                "commands",
                "setpoints and raw actuator commands at once: a vehicle follows one or the other",
            ));
        }
        let get = |k: &str| commands.get_item(k).ok().flatten();
        let vehicles = get("vehicles");
        if raw {
            self.set_actuators(
                py,
                get("thrusters").as_ref(),
                get("tilts").as_ref(),
                get("pump").as_ref(),
                vehicles.as_ref(),
                clip,
            )
        } else if sp {
            let mode = get("mode");
            self.set_setpoints(
                py,
                get("depth").as_ref(),
                get("yaw").as_ref(),
                get("surge").as_ref(),
                get("sway").as_ref(),
                mode.as_ref(),
                vehicles.as_ref(),
                clip,
            )
        } else {
            Ok(())
        }
    }

    /// Per-vehicle limits as a (vehicles, `width`) array from `f(vehicle, column)`.
    fn per_actuator<'py, T: numpy::Element + Default + Clone>(
        &self,
        py: Python<'py>,
        width: usize,
        f: impl Fn(&shoal_model::vehicle::VehicleParams, usize) -> Option<T>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let n = self.desc.vehicles.len();
        let mut data = vec![T::default(); n * width];
        for (v, row) in self.desc.vehicles.iter().zip(data.chunks_mut(width.max(1))) {
            for (i, x) in row.iter_mut().enumerate().take(width) {
                if let Some(y) = f(&v.model.params, i) {
                    *x = y;
                }
            }
        }
        Ok(Array2::from_shape_vec((n, width), data)
            .map_err(|e| PyValueError::new_err(e.to_string()))?
            .into_pyarray(py)
            .into_any())
    }
}

#[pymethods]
impl World {
    #[new]
    #[pyo3(signature = (world=None, seed=None, threads=None))]
    fn new(
        py: Python<'_>,
        world: Option<&Bound<'_, PyAny>>,
        seed: Option<u64>,
        threads: Option<usize>,
    ) -> PyResult<Self> {
        let source = Source::of(world)?;
        let desc = source.load(py, seed)?;
        let threads = source::threads(threads)?;
        for w in &desc.warnings {
            let msg = std::ffi::CString::new(format!("{}: {w}", desc.source.display()))
                .unwrap_or_default();
            PyErr::warn(py, &py.get_type::<PyUserWarning>(), &msg, 1)?;
        }
        let mut sim = build(py, &desc, threads);
        let shape = sim.batch_shape();
        let tick = sim.control_steps();
        let max_payload = desc
            .vehicles
            .iter()
            .flat_map(|v| v.model.params.modems.iter().map(|m| m.max_payload))
            .max()
            .unwrap_or(0);
        Ok(Self {
            source,
            desc,
            sim,
            threads,
            shape,
            tick,
            max_payload,
            received: Arrivals::default(),
            warned_sync: false,
        })
    }

    /// Rebuilds the world at t = 0 with `seed` (default: the seed in force), exactly as a
    /// new `World` of the same file and seed (another seed reads the world again: the seed
    /// draws its placement too).
    #[pyo3(signature = (seed=None))]
    fn reset(&mut self, py: Python<'_>, seed: Option<u64>) -> PyResult<()> {
        if let Some(s) = seed.filter(|&s| s != self.desc.seed) {
            self.desc = self.source.load(py, Some(s))?;
        }
        self.sim = build(py, &self.desc, self.threads);
        self.received.clear();
        Ok(())
    }

    /// Applies `commands` (a dict, see below) and advances `steps` physics steps (default:
    /// one control period, `tick_steps`). Afterwards `received` holds the frames delivered
    /// during these steps.
    ///
    /// `commands` holds either setpoints — `mode` (name, code or array of codes; default
    /// `"auto"`), `depth` [m], `yaw` [rad], `surge` [N], `sway` [N] — or raw actuator commands
    /// — `thrusters` [%] (vehicles × `n_thrusters` columns), `tilts` [rad], `pump` (−1, 0, 1)
    /// — and optionally `vehicles` (ids; default all, in id order). Each value is a number
    /// for all vehicles or an array with one entry per vehicle. Fields left out keep their
    /// values. Every value is checked before anything changes: NaN, infinity, unknown modes
    /// and (unless `clip=True`, which clamps them) values out of range raise `CommandError`
    /// naming the vehicle, the field and the allowed range. Raises `SimulationError` if a
    /// vehicle's state stops being finite.
    #[pyo3(signature = (commands=None, steps=None, clip=false))]
    fn step(
        &mut self,
        py: Python<'_>,
        commands: Option<&Bound<'_, PyDict>>,
        steps: Option<u64>,
        clip: bool,
    ) -> PyResult<()> {
        if let Some(c) = commands {
            self.apply(py, c, clip)?;
        }
        self.advance(py, steps.unwrap_or(self.tick), true)
    }

    /// Advances `seconds` of simulated time (rounded to whole physics steps, as `shoal run
    /// --duration`) without commands; `received` is left empty.
    fn run(&mut self, py: Python<'_>, seconds: f64) -> PyResult<()> {
        if !(seconds.is_finite() && seconds >= 0.0) {
            return Err(PyValueError::new_err(format!(
                "seconds = {seconds}: allowed a finite time ≥ 0 s"
            )));
        }
        let steps = (seconds / self.desc.dt).round() as u64;
        self.advance(py, steps, false)
    }

    /// Sets setpoints of all vehicles (or of `vehicles`) for the built-in controller: `mode`
    /// (default `"auto"`), `depth` [m, 0 … pool depth], `yaw` [rad], `surge` and `sway` [N,
    /// within ± `limits["force_max"]`]; fields left `None` keep their values. See `step` for
    /// the checks and `clip`.
    #[pyo3(signature = (depth=None, yaw=None, surge=None, sway=None, mode=None, vehicles=None, clip=false))]
    fn set_setpoints(
        &mut self,
        py: Python<'_>,
        depth: Option<&Bound<'_, PyAny>>,
        yaw: Option<&Bound<'_, PyAny>>,
        surge: Option<&Bound<'_, PyAny>>,
        sway: Option<&Bound<'_, PyAny>>,
        mode: Option<&Bound<'_, PyAny>>,
        vehicles: Option<&Bound<'_, PyAny>>,
        clip: bool,
    ) -> PyResult<()> {
        let ids = args::vehicle_ids(vehicles)?;
        fn col<'py>(
            o: Option<&Bound<'py, PyAny>>,
            name: &str,
        ) -> PyResult<Option<args::FloatCol<'py>>> {
            o.filter(|x| !x.is_none())
                .map(|x| args::float_column(x, name))
                .transpose()
        }
        let (d, y, su, sw) = (
            col(depth, "depth")?,
            col(yaw, "yaw")?,
            col(surge, "surge")?,
            col(sway, "sway")?,
        );
        let mode = match mode.filter(|m| !m.is_none()) {
            None => args::IntCol::Scalar(5),
            Some(m) => args::mode_column(m)?,
        };
        let order = SetpointOrder {
            mode: mode.column(),
            depth: d.as_ref().map(|c| c.column()),
            yaw: y.as_ref().map(|c| c.column()),
            surge: su.as_ref().map(|c| c.column()),
            sway: sw.as_ref().map(|c| c.column()),
        };
        self.sim
            .set_setpoints(ids.as_deref(), &order, clip)
            .map_err(|e| command_error(py, &e))
    }

    /// Sets raw actuator commands (mode raw) of all vehicles (or of `vehicles`): `thrusters`
    /// [% of full scale, within ± `limits["thruster_max"]`] as a (vehicles, `n_thrusters`
    /// max) array, `tilts` [rad, within `limits["tilt_min"]` … `limits["tilt_max"]`] as a
    /// (vehicles, tilts) array, `pump` (−1 empty, 0 off, +1 fill); a 1-D row is used for
    /// every vehicle. Columns beyond a vehicle's own actuators must be 0. See `step` for the
    /// checks and `clip`.
    #[pyo3(signature = (thrusters=None, tilts=None, pump=None, vehicles=None, clip=false))]
    fn set_actuators(
        &mut self,
        py: Python<'_>,
        thrusters: Option<&Bound<'_, PyAny>>,
        tilts: Option<&Bound<'_, PyAny>>,
        pump: Option<&Bound<'_, PyAny>>,
        vehicles: Option<&Bound<'_, PyAny>>,
        clip: bool,
    ) -> PyResult<()> {
        let ids = args::vehicle_ids(vehicles)?;
        let rows = ids.as_ref().map_or(self.shape.vehicles, Vec::len);
        let matrix = |o: Option<&Bound<'_, PyAny>>, name: &str, width: usize| {
            o.filter(|x| !x.is_none())
                .map(|x| args::float_rows(x, name, rows, width))
                .transpose()
        };
        let th: Option<FloatRows> = matrix(thrusters, "thrusters", self.shape.thrusters)?;
        let tl: Option<FloatRows> = matrix(tilts, "tilts", self.shape.tilts)?;
        let pump = pump
            .filter(|x| !x.is_none())
            .map(|p| args::int_column(p, "pump"))
            .transpose()?;
        let order = ActuatorOrder {
            thrusters: th.as_ref().map(FloatRows::rows),
            tilts: tl.as_ref().map(FloatRows::rows),
            pump: pump.as_ref().map(args::IntCol::column),
        };
        self.sim
            .set_actuators(ids.as_deref(), &order, clip)
            .map_err(|e| command_error(py, &e))
    }

    /// Hands frames to vehicles' modems: `vehicles` (one id or an array of k ids), `payload`
    /// (bytes for all, a sequence of k bytes objects, or a (k, length) uint8 array), `modem`
    /// (None or −1: every modem of the vehicle in sync; else an index or k indices), `delay`
    /// after now [s, 0 … `MAX_FRAME_DELAY`] (number or k values). Vehicles whose modems start
    /// at the same instant cannot hear each other (a modem is half-duplex: it is deaf while
    /// it transmits), so spread the delays of vehicles that send together (a `UserWarning`
    /// says so, once, when the frames of several vehicles all have the same delay). Every frame is
    /// `to` (None or −1: a broadcast; else the destination vehicle's id, or k of them) sends
    /// a unicast, which only its destination takes; with `ack` (a bool or k bools) the
    /// destination acknowledges it and the sender retransmits it until it does or the modem's
    /// `arq_retries` are used up — what became of it is in `outcomes` after the step it ended
    /// in, with its `tag` (an integer 0 … 2³² − 1 of your choosing, or k of them). Every frame
    /// is checked first (payload length 1 … the modem's `max_payload`, modem index, delay,
    /// destination another vehicle, `ack` only with a destination); nothing is queued on an
    /// error.
    #[pyo3(signature = (vehicles, payload, modem=None, delay=None, to=None, ack=None, tag=None, clip=false))]
    #[allow(clippy::too_many_arguments)]
    fn send(
        &mut self,
        py: Python<'_>,
        vehicles: &Bound<'_, PyAny>,
        payload: &Bound<'_, PyAny>,
        modem: Option<&Bound<'_, PyAny>>,
        delay: Option<&Bound<'_, PyAny>>,
        to: Option<&Bound<'_, PyAny>>,
        ack: Option<&Bound<'_, PyAny>>,
        tag: Option<&Bound<'_, PyAny>>,
        clip: bool,
    ) -> PyResult<()> {
        let zero = 0.0f64.into_pyobject(py)?.into_any();
        let frames = args::frames(&args::SendArgs {
            vehicles,
            payload,
            modem,
            delay: delay.unwrap_or(&zero),
            to,
            ack,
            tag,
        })?;
        self.sim
            .queue_frames(&frames, clip)
            .map_err(|e| command_error(py, &e))?;
        args::warn_if_simultaneous(py, &frames, &mut self.warned_sync)
    }

    /// Quantity `name` (one of `QUANTITIES`) of every vehicle as a fresh numpy array, one row
    /// per vehicle in id order (the same as the attribute of that name).
    fn read<'py>(&mut self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        let q = Quantity::from_name(name).ok_or_else(|| {
            PyValueError::new_err(format!(
                "`{name}` is not a quantity: use one of {}",
                Quantity::ALL.map(Quantity::name).join(", ")
            ))
        })?;
        self.quantity(py, q)
    }

    /// The quantities `names` (default: all of `QUANTITIES`) as a dict of numpy arrays.
    #[pyo3(signature = (names=None))]
    fn observe<'py>(
        &mut self,
        py: Python<'py>,
        names: Option<Vec<String>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        match names {
            None => {
                for q in Quantity::ALL {
                    d.set_item(q.name(), self.quantity(py, q)?)?;
                }
            }
            Some(ns) => {
                for n in ns {
                    let a = self.read(py, &n)?;
                    d.set_item(n, a)?;
                }
            }
        }
        Ok(d)
    }

    /// The frames delivered during the last `step()` (empty after `run`, `reset`): a dict of
    /// parallel numpy arrays, one entry per frame in receiver id order — `vehicle`
    /// (receiver), `sender`, `seq`, `modem` (receiving modem), `t` (end of reception [s]),
    /// `sent` (handed over by the sender [s]), `power` (received optical power [W]), `snr`
    /// (linear), `unicast` (bool: sent to this vehicle alone), `length` [bytes], `payload`
    /// (uint8, frames × the world's largest `max_payload`, zero after `length`).
    #[getter]
    fn received<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        observe::received(py, &self.received.frames, self.max_payload)
    }

    /// What became of acknowledged unicasts (`send(..., to=…, ack=True)`) during the last
    /// `step()` (empty after `run`, `reset`): a dict of parallel numpy arrays, one entry per
    /// frame in sender id order — `vehicle` (sender), `to` (destination), `tag` (as given to
    /// `send`), `seq` (the sender's frame number), `acknowledged` (bool; False: given up after
    /// its retries, or refused by a full queue with `transmissions` 0), `transmissions`
    /// (1 + retransmissions), `sent` (handed over [s]), `t` (acknowledgement decoded, or the
    /// last wait ended [s]).
    #[getter]
    fn outcomes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        observe::outcomes(py, &self.received.outcomes)
    }

    /// Frames delivered to each vehicle during the last `step()` (vehicles,), int64.
    #[getter]
    fn received_count<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let mut c = vec![0i64; self.shape.vehicles];
        for (id, _) in &self.received.frames {
            c[*id as usize] += 1;
        }
        c.into_pyarray(py).into_any()
    }

    /// Command limits, a dict: `depth_max` [m] (the pool's depth; depth setpoints 0 …
    /// depth_max), `force_max` (vehicles,) [N] (|surge|, |sway|), `thruster_max` (vehicles,
    /// thrusters) [%], `tilt_min` and `tilt_max` (vehicles, tilts) [rad], `payload_max`
    /// (vehicles, modems) [bytes], `has_tank` (vehicles,) bool; 0 beyond a vehicle's own
    /// actuators and modems.
    #[getter]
    fn limits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        let s = &self.shape;
        d.set_item("depth_max", self.desc.geometry.pool.z)?;
        let vs = &self.desc.vehicles;
        d.set_item(
            "force_max",
            vs.iter()
                .map(|v| force_limit(&v.model))
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        d.set_item(
            "thruster_max",
            self.per_actuator(py, s.thrusters, |p, i| {
                p.thrusters.get(i).map(|t| t.max_command)
            })?,
        )?;
        d.set_item(
            "tilt_min",
            self.per_actuator(py, s.tilts, |p, i| p.tilts.get(i).map(|t| t.min))?,
        )?;
        d.set_item(
            "tilt_max",
            self.per_actuator(py, s.tilts, |p, i| p.tilts.get(i).map(|t| t.max))?,
        )?;
        d.set_item(
            "payload_max",
            self.per_actuator(py, s.modems, |p, i| {
                p.modems.get(i).map(|m| m.max_payload as i64)
            })?,
        )?;
        d.set_item(
            "has_tank",
            vs.iter()
                .map(|v| v.model.params.ballast.is_some())
                .collect::<Vec<_>>()
                .into_pyarray(py),
        )?;
        Ok(d)
    }

    /// The state digest as `shoal run` writes it to summary.json (16 hex digits, FNV-1a of
    /// every vehicle's full state): equal digests mean bit-identical runs.
    #[getter]
    fn digest(&self) -> String {
        format!("{:016x}", self.sim.digest())
    }

    /// Simulated time [s].
    #[getter]
    fn time(&self) -> f64 {
        self.sim.time()
    }

    /// Physics steps done since the start.
    #[getter]
    fn step_count(&self) -> u64 {
        self.sim.step_count()
    }

    /// Physics step [s].
    #[getter]
    fn dt(&self) -> f64 {
        self.desc.dt
    }

    /// Physics steps of one control period (the shortest of any vehicle): one `step()`.
    #[getter]
    fn tick_steps(&self) -> u64 {
        self.tick
    }

    /// Duration of one `step()` by default, `tick_steps · dt` [s].
    #[getter]
    fn control_dt(&self) -> f64 {
        self.tick as f64 * self.desc.dt
    }

    /// The world file's duration [s] (`shoal run` stops there; `World` does not).
    #[getter]
    fn duration(&self) -> f64 {
        self.desc.duration
    }

    /// The seed in force.
    #[getter]
    fn seed(&self) -> u64 {
        self.desc.seed
    }

    /// Working threads.
    #[getter]
    fn threads(&self) -> usize {
        self.threads
    }

    /// The loops split over the thread pool since the world was built or reset, per kind:
    /// `{"behaviour": n, "vehicles": n, "delivery": n, "links": n, "walk": n}` (as
    /// `parallel_dispatches` in `shoal run`'s summary.json; `walk`: transmit walks split into
    /// parts). All zero on one thread and for loops under 256 vehicles.
    #[getter]
    fn parallel_dispatches<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let p = self.sim.parallel_dispatches();
        let d = PyDict::new(py);
        d.set_item("behaviour", p.behaviour)?;
        d.set_item("vehicles", p.vehicles)?;
        d.set_item("delivery", p.delivery)?;
        d.set_item("links", p.links)?;
        d.set_item("walk", p.walk)?;
        Ok(d)
    }

    /// The world's name.
    #[getter]
    fn name(&self) -> String {
        self.desc.name.clone()
    }

    /// Vehicle names in id order.
    #[getter]
    fn names(&self) -> Vec<String> {
        self.desc.vehicles.iter().map(|v| v.name.clone()).collect()
    }

    /// Vehicle group of each vehicle (index into `group_names`), (vehicles,) int64.
    #[getter]
    fn groups<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        let g: Vec<i64> = self.desc.vehicles.iter().map(|v| v.group as i64).collect();
        g.into_pyarray(py).into_any()
    }

    /// Names of the world file's vehicle groups.
    #[getter]
    fn group_names(&self) -> Vec<String> {
        self.desc.groups.clone()
    }

    /// Pool length (north), width (east) and depth [m].
    #[getter]
    fn pool_size(&self) -> (f64, f64, f64) {
        let p = self.desc.geometry.pool;
        (p.x, p.y, p.z)
    }

    /// Thrusters, tilt drives and modems of each vehicle: (vehicles, 3) int64.
    #[getter]
    fn actuator_counts<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.per_actuator(py, 3, |p, i| {
            Some([p.thrusters.len(), p.tilts.len(), p.modems.len()][i] as i64)
        })
    }

    /// Why the world cannot continue (a vehicle's state stopped being finite), or None.
    #[getter]
    fn fault(&self) -> Option<String> {
        self.sim.fault().map(ToString::to_string)
    }

    /// Number of vehicles.
    #[getter]
    fn n(&self) -> usize {
        self.shape.vehicles
    }

    fn __len__(&self) -> usize {
        self.shape.vehicles
    }

    fn __repr__(&self) -> String {
        format!(
            "World({:?}: {} vehicles, t = {:.2} s, seed {}, {} thread(s))",
            self.desc.name,
            self.shape.vehicles,
            self.sim.time(),
            self.desc.seed,
            self.threads
        )
    }

    /// True position of each body origin, world frame (north, east, down): (vehicles, 3) [m].
    #[getter]
    fn position<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Position)
    }

    /// True attitude quaternion body → world (w, x, y, z): (vehicles, 4).
    #[getter]
    fn attitude<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Attitude)
    }

    /// True roll, pitch, yaw: (vehicles, 3) [rad].
    #[getter]
    fn euler<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Euler)
    }

    /// Velocity relative to the water, body frame (u, v, w [m/s], p, q, r [rad/s]):
    /// (vehicles, 6).
    #[getter]
    fn velocity<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Velocity)
    }

    /// Velocity over ground, world frame: (vehicles, 3) [m/s].
    #[getter]
    fn world_velocity<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::WorldVelocity)
    }

    /// Depth reading of the pressure sensor (quantised, noisy): (vehicles,) [m].
    #[getter]
    fn depth_reading<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::DepthReading)
    }

    /// Roll, pitch, yaw of the IMU's attitude estimate: (vehicles, 3) [rad].
    #[getter]
    fn imu_euler<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::ImuEuler)
    }

    /// Body rates from the gyros: (vehicles, 3) [rad/s].
    #[getter]
    fn gyro<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Gyro)
    }

    /// Specific force from the accelerometer, body frame: (vehicles, 3) [m/s²].
    #[getter]
    fn accel<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Accel)
    }

    /// Tilt angles from the potentiometers: (vehicles, tilts) [rad].
    #[getter]
    fn tilt_reading<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::TiltReading)
    }

    /// The tank's full switch: (vehicles,) bool.
    #[getter]
    fn tank_full<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::TankFull)
    }

    /// Actual thrust per thruster: (vehicles, thrusters) [N].
    #[getter]
    fn thrust<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Thrust)
    }

    /// Actual tilt angle per tilt drive: (vehicles, tilts) [rad].
    #[getter]
    fn tilt_angle<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::TiltAngle)
    }

    /// Water in the buoyancy tank: (vehicles,) [m³].
    #[getter]
    fn ballast<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Ballast)
    }

    /// Thruster commands in force: (vehicles, thrusters) [% of full scale].
    #[getter]
    fn thruster_command<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::ThrusterCommand)
    }

    /// Controller mode code (index in `MODES`; 6: raw): (vehicles,) int64.
    #[getter]
    fn mode<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Mode)
    }

    /// Setpoints in force (depth [m], heading [rad], surge [N], sway [N]): (vehicles, 4).
    #[getter]
    fn setpoint<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Setpoint)
    }

    /// Frames waiting in each modem's transmit queue: (vehicles, modems) int64.
    #[getter]
    fn modem_queued<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::ModemQueued)
    }

    /// Frames put on the air since the start: (vehicles,) int64.
    #[getter]
    fn frames_sent<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::FramesSent)
    }

    /// Frames delivered to each vehicle since the start: (vehicles,) int64.
    #[getter]
    fn frames_received<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::FramesReceived)
    }

    /// Receptions lost since the start, by cause (range or angle, occlusion, collision,
    /// half-duplex): (vehicles, 4) int64.
    #[getter]
    fn frames_lost<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::FramesLost)
    }

    /// Whether the hull touched a wall, the floor or an obstacle in the last step:
    /// (vehicles,) bool.
    #[getter]
    fn touching<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.quantity(py, Quantity::Touching)
    }
}
