//! One vehicle's ROS 2 topics: what the world publishes for it and the commands it reads,
//! under `/<namespace>/<vehicle>/`, with ROS 2's names (`rt/…` topics, `pkg::msg::dds_::Type_`
//! types — `ros2-client` forms them) and QoS that ROS 2 nodes accept: sensor data best
//! effort (keep last 10, as `rclcpp::SensorDataQoS`), frames, their outcomes and commands
//! reliable (keep last 100).

use crate::error::Ros2Error;
use crate::msgs::{
    Actuators, Clock, FluidPressure, FrameOutcome, Imu, Odometry, OpticalFrame, Setpoint, TfMessage,
};
use crate::names::ros_name;
use ros2_client::{
    MessageTypeName, Name, Node, Publisher, QosProfile, Subscription,
    qos::{History, Reliability, WhenFull},
};
use serde::Serialize;
use std::time::Duration;

/// Sensor data: best effort, keep last 10.
pub fn sensor_qos() -> QosProfile {
    QosProfile {
        reliability: Reliability::BestEffort,
        history: History::KeepLast { depth: 10 },
        ..QosProfile::subscription_default()
    }
}

/// Commands and frames: reliable, keep last 100.
pub fn command_qos() -> QosProfile {
    QosProfile {
        reliability: Reliability::Reliable {
            when_full: WhenFull::Wait(Duration::from_millis(100)),
        },
        history: History::KeepLast { depth: 100 },
        ..QosProfile::subscription_default()
    }
}

/// A publisher of `T` on `namespace`/`leaf` typed `pkg/T`.
pub fn publisher<T: Serialize>(
    node: &mut Node,
    namespace: &str,
    leaf: &str,
    ty: (&str, &str),
    qos: &QosProfile,
) -> Result<Publisher<T>, Ros2Error> {
    let name = Name::new(namespace, leaf)
        .map_err(|e| Ros2Error::Name(format!("{namespace}/{leaf}: {e:?}")))?;
    let topic = node
        .create_topic(&name, MessageTypeName::new(ty.0, ty.1), qos)
        .map_err(|e| Ros2Error::Dds(format!("topic {namespace}/{leaf}: {e:?}")))?;
    node.create_publisher::<T>(&topic, Some(qos.clone()))
        .map_err(|e| Ros2Error::Dds(format!("publisher {namespace}/{leaf}: {e:?}")))
}

/// A subscription to `T` on `namespace`/`leaf` typed `pkg/T`.
pub fn subscription<T: 'static>(
    node: &mut Node,
    namespace: &str,
    leaf: &str,
    ty: (&str, &str),
    qos: &QosProfile,
) -> Result<Subscription<T>, Ros2Error> {
    let name = Name::new(namespace, leaf)
        .map_err(|e| Ros2Error::Name(format!("{namespace}/{leaf}: {e:?}")))?;
    let topic = node
        .create_topic(&name, MessageTypeName::new(ty.0, ty.1), qos)
        .map_err(|e| Ros2Error::Dds(format!("topic {namespace}/{leaf}: {e:?}")))?;
    node.create_subscription::<T>(&topic, Some(qos.clone()))
        .map_err(|e| Ros2Error::Dds(format!("subscription {namespace}/{leaf}: {e:?}")))
}

/// The topics of one vehicle.
pub struct VehicleTopics {
    /// Vehicle id.
    pub id: u32,
    /// Its name as a ROS 2 name ([`ros_name`]; `/<namespace>/<name>/…`).
    pub name: String,
    /// `imu` (sensor_msgs/Imu).
    pub imu: Publisher<Imu>,
    /// `pressure` (sensor_msgs/FluidPressure).
    pub pressure: Publisher<FluidPressure>,
    /// `odom` (nav_msgs/Odometry), when the world grants positions.
    pub odom: Option<Publisher<Odometry>>,
    /// `modem/rx` (shoal_msgs/OpticalFrame).
    pub rx: Publisher<OpticalFrame>,
    /// `modem/outcome` (shoal_msgs/FrameOutcome).
    pub outcome: Publisher<FrameOutcome>,
    /// `setpoint` (shoal_msgs/Setpoint).
    pub setpoint: Subscription<Setpoint>,
    /// `actuators` (shoal_msgs/Actuators).
    pub actuators: Subscription<Actuators>,
    /// `modem/tx` (shoal_msgs/OpticalFrame).
    pub tx: Subscription<OpticalFrame>,
}

impl VehicleTopics {
    /// Creates the topics of vehicle `id` named `name` under `/<namespace>/<name>`.
    pub fn open(
        node: &mut Node,
        namespace: &str,
        id: u32,
        name: &str,
        grant_position: bool,
    ) -> Result<Self, Ros2Error> {
        let name = ros_name(name);
        let ns = format!("/{namespace}/{name}");
        let modem = format!("{ns}/modem");
        let (sensor, command) = (sensor_qos(), command_qos());
        Ok(Self {
            id,
            name,
            imu: publisher(node, &ns, "imu", ("sensor_msgs", "Imu"), &sensor)?,
            pressure: publisher(
                node,
                &ns,
                "pressure",
                ("sensor_msgs", "FluidPressure"),
                &sensor,
            )?,
            odom: if grant_position {
                Some(publisher(
                    node,
                    &ns,
                    "odom",
                    ("nav_msgs", "Odometry"),
                    &sensor,
                )?)
            } else {
                None
            },
            rx: publisher(node, &modem, "rx", ("shoal_msgs", "OpticalFrame"), &command)?,
            outcome: publisher(
                node,
                &modem,
                "outcome",
                ("shoal_msgs", "FrameOutcome"),
                &command,
            )?,
            setpoint: subscription(node, &ns, "setpoint", ("shoal_msgs", "Setpoint"), &command)?,
            actuators: subscription(
                node,
                &ns,
                "actuators",
                ("shoal_msgs", "Actuators"),
                &command,
            )?,
            tx: subscription(node, &modem, "tx", ("shoal_msgs", "OpticalFrame"), &command)?,
        })
    }
}

/// The world-wide topics: `/clock` and, with positions granted, `/tf`.
pub struct WorldTopics {
    /// `/clock` (rosgraph_msgs/Clock), best effort, once per control tick.
    pub clock: Publisher<Clock>,
    /// `/tf` (tf2_msgs/TFMessage): every bridged vehicle's true pose, when granted.
    pub tf: Option<Publisher<TfMessage>>,
}

impl WorldTopics {
    /// Creates them.
    pub fn open(node: &mut Node, grant_position: bool) -> Result<Self, Ros2Error> {
        let clock_qos = QosProfile {
            history: History::KeepLast { depth: 1 },
            ..sensor_qos()
        };
        Ok(Self {
            clock: publisher(node, "/", "clock", ("rosgraph_msgs", "Clock"), &clock_qos)?,
            tf: if grant_position {
                Some(publisher(
                    node,
                    "/",
                    "tf",
                    ("tf2_msgs", "TFMessage"),
                    &command_qos(),
                )?)
            } else {
                None
            },
        })
    }
}
