//! FMI 3.0 calls ([`Op3`]) and their generation, as seq.rs does for FMI 2.0: part of the time
//! following the FMI 3.0 state machine of the instance (instantiated for co-simulation or
//! Model Exchange, `parameterFile` and the coefficient arrays set, initialized, stepping or
//! in continuous-time mode, FMU states saved, restored, serialized and read back), the rest
//! any call with any arguments: wrong `nValues`, value references of another type or of no
//! variable, NULL arrays with a length, NaN and infinities, bad instantiation tokens, a NULL
//! `logMessage`, derivatives with mismatched `nSeed` / `nSensitivity` or of arrays and
//! parameters, the functions of types, clocks and interfaces the FMU does not have.
//!
//! The variables are read from the FMI 3.0 model description, the one place they are
//! written.

use std::sync::OnceLock;

use crate::seq::{
    Arr, Corrupt, Expect, Generator, HOSTILE, INSTANCES, STATE_SLOTS, StateRef, Str, Time,
    Transition, random_state_op,
};

/// The FMI 3.0 model description the variables come from.
const MODEL_DESCRIPTION: &str = include_str!("../../modelDescription/fmi3/modelDescription.xml");

/// The type of an FMI 3.0 variable of this FMU.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Type3 {
    Float64,
    Boolean,
    String,
}

/// One FMI 3.0 variable.
#[derive(Debug, Clone)]
pub struct Var3 {
    pub vr: u32,
    pub name: String,
    pub ty: Type3,
    /// Elements: 1 for a scalar, the dimension of an array.
    pub size: usize,
    /// The start values of a Float64 (one per element; empty without a start).
    pub starts: Vec<f64>,
}

/// The FMI 3.0 variables by role, and the model structure's counts.
#[derive(Debug)]
pub struct Vars3 {
    pub vars: Vec<Var3>,
    /// The independent variable.
    pub time: u32,
    pub inputs: Vec<u32>,
    pub speed: u32,
    pub conditions: Vec<u32>,
    pub outputs: Vec<u32>,
    /// Float64 scalar parameters.
    pub parameters: Vec<u32>,
    /// Float64 array parameters (the coefficient tables).
    pub arrays: Vec<u32>,
    /// Continuous states and their derivatives (locals).
    pub states: Vec<u32>,
    pub derivatives: Vec<u32>,
    pub booleans: Vec<u32>,
    pub strings: Vec<u32>,
    pub float64: Vec<u32>,
    /// The references of every variable and of none.
    pub every: Vec<u32>,
    /// The scalar parameters and (three times as often) the coefficient arrays.
    pub parameter_pool: Vec<u32>,
    /// The model inputs and vx; the same with p and T_tread.
    pub inputs_speed: Vec<u32>,
    pub inputs_all: Vec<u32>,
    pub n_states: usize,
    pub n_indicators: usize,
}

/// Value references of no FMI 3.0 variable: gaps, FMI 2.0's coefficient elements, the
/// largest.
pub const UNKNOWN: &[u32] = &[
    u32::MAX,
    99,
    18,
    19,
    22,
    101,
    113,
    213,
    301,
    399,
    1001,
    12345,
];

impl Vars3 {
    /// Parsed once per process.
    pub fn get() -> &'static Vars3 {
        static VARS: OnceLock<Vars3> = OnceLock::new();
        VARS.get_or_init(|| Vars3::parse(MODEL_DESCRIPTION))
    }

    pub fn var(&self, vr: u32) -> Option<&Var3> {
        self.vars.iter().find(|v| v.vr == vr)
    }

    /// The variable `vr` if it is a Float64.
    pub fn float64(&self, vr: u32) -> Option<&Var3> {
        self.var(vr).filter(|v| v.ty == Type3::Float64)
    }

    fn parse(xml: &str) -> Vars3 {
        let start = xml.find("<ModelVariables>").expect("ModelVariables");
        let end = xml.find("</ModelVariables>").expect("/ModelVariables");
        let section = &xml[start..end];
        let mut vars = Vec::new();
        let mut roles: Vec<(u32, String, String)> = Vec::new();
        let mut at = 0;
        while let Some(i) = section[at..].find('<') {
            let tag_start = at + i;
            let rest = &section[tag_start + 1..];
            let ty = [
                ("Float64 ", Type3::Float64),
                ("Boolean ", Type3::Boolean),
                ("String ", Type3::String),
            ]
            .into_iter()
            .find(|(t, _)| rest.starts_with(t));
            let tag_end = tag_start + end_of_tag(&section[tag_start..]);
            at = tag_end;
            let Some((t, ty)) = ty else { continue };
            let tag = &section[tag_start..tag_end];
            let name = attribute(tag, "name").expect("name").to_string();
            let vr: u32 = attribute(tag, "valueReference")
                .expect("valueReference")
                .parse()
                .expect("a number");
            let causality = attribute(tag, "causality").unwrap_or("local").to_string();
            let mut size = 1;
            if !tag.ends_with("/>") {
                let close = format!("</{}>", t.trim());
                let body_end = at + section[at..].find(&close).expect("closing tag");
                let body = &section[at..body_end];
                let mut b = 0;
                while let Some(d) = body[b..].find("<Dimension ") {
                    let dim_end = b + d + end_of_tag(&body[b + d..]);
                    let dim = &body[b + d..dim_end];
                    size *= attribute(dim, "start")
                        .expect("a fixed dimension")
                        .parse::<usize>()
                        .expect("a number");
                    b = dim_end;
                }
                at = body_end;
            }
            let starts = match (ty, attribute(tag, "start")) {
                (Type3::Float64, Some(s)) => s
                    .split_whitespace()
                    .map(|x| x.parse().expect("a number"))
                    .collect(),
                _ => Vec::new(),
            };
            roles.push((vr, name.clone(), causality));
            vars.push(Var3 {
                vr,
                name,
                ty,
                size,
                starts,
            });
        }
        let structure = &xml[end..];
        let of = |want: &dyn Fn(&Var3, &str) -> bool| -> Vec<u32> {
            vars.iter()
                .zip(&roles)
                .filter(|(v, (_, _, causality))| want(v, causality))
                .map(|(v, _)| v.vr)
                .collect()
        };
        let f64s = |v: &Var3| v.ty == Type3::Float64;
        let time = of(&|_, c| c == "independent");
        let speed = of(&|v, c| c == "input" && v.name == "vx");
        let mut out = Vars3 {
            every: Vec::new(),
            parameter_pool: Vec::new(),
            inputs_speed: Vec::new(),
            inputs_all: Vec::new(),
            time: time[0],
            inputs: of(&|v, c| {
                c == "input" && f64s(v) && !["vx", "p", "T_tread"].contains(&v.name.as_str())
            }),
            speed: speed[0],
            conditions: of(&|v, c| c == "input" && ["p", "T_tread"].contains(&v.name.as_str())),
            outputs: of(&|_, c| c == "output"),
            parameters: of(&|v, c| c == "parameter" && f64s(v) && v.size == 1),
            arrays: of(&|v, c| c == "parameter" && f64s(v) && v.size > 1),
            states: of(&|v, c| c == "local" && f64s(v) && !v.name.starts_with("der(")),
            derivatives: of(&|v, c| c == "local" && v.name.starts_with("der(")),
            booleans: of(&|v, _| v.ty == Type3::Boolean),
            strings: of(&|v, _| v.ty == Type3::String),
            float64: of(&|v, _| f64s(v)),
            n_states: structure.matches("<ContinuousStateDerivative ").count(),
            n_indicators: structure.matches("<EventIndicator ").count(),
            vars,
        };
        assert!(
            out.inputs.len() == 4
                && out.outputs.len() == 3
                && out.arrays.len() == 3
                && out.states.len() == out.n_states
                && out.booleans.len() == 1
                && out.strings.len() == 1,
            "unexpected FMI 3.0 variables: {out:?}"
        );
        assert!(UNKNOWN.iter().all(|vr| out.var(*vr).is_none()));
        out.every = out
            .vars
            .iter()
            .map(|v| v.vr)
            .chain(UNKNOWN.iter().copied())
            .collect();
        out.parameter_pool = out.parameters.clone();
        for _ in 0..3 {
            out.parameter_pool.extend(&out.arrays);
        }
        out.inputs_speed = out.inputs.clone();
        out.inputs_speed.push(out.speed);
        out.inputs_all = out.inputs_speed.clone();
        out.inputs_all.extend(&out.conditions);
        out
    }
}

/// The length of the tag starting at `s[0] == '<'`, up to and with its `>` (quotes skipped).
fn end_of_tag(s: &str) -> usize {
    let mut quoted = false;
    for (i, c) in s.char_indices() {
        match c {
            '"' => quoted = !quoted,
            '>' if !quoted => return i + 1,
            _ => {}
        }
    }
    s.len()
}

/// The value of attribute `name` in the tag `tag`.
fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!("{name}=\"");
    let mut from = 0;
    while let Some(i) = tag[from..].find(&key) {
        let at = from + i;
        if tag[..at].ends_with(char::is_whitespace) {
            let value = &tag[at + key.len()..];
            return value.find('"').map(|e| &value[..e]);
        }
        from = at + key.len();
    }
    None
}

/// How an FMI 3.0 instance is made.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Interface3 {
    ModelExchange,
    CoSimulation,
    /// Not offered: must be refused.
    ScheduledExecution,
}

/// The FMI 3.0 functions that take only the instance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Plain {
    ExitInitializationMode,
    EnterEventMode,
    Terminate,
    Reset,
    EnterContinuousTimeMode,
    EvaluateDiscreteStates,
    EnterConfigurationMode,
    ExitConfigurationMode,
    EnterStepMode,
}

const PLAIN: &[Plain] = &[
    Plain::ExitInitializationMode,
    Plain::EnterEventMode,
    Plain::Terminate,
    Plain::Reset,
    Plain::EnterContinuousTimeMode,
    Plain::EvaluateDiscreteStates,
    Plain::EnterConfigurationMode,
    Plain::ExitConfigurationMode,
    Plain::EnterStepMode,
];

/// The types this FMU has no variable of: their getters and setters must refuse any value
/// reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Absent {
    Float32,
    Int8,
    UInt8,
    Int16,
    UInt16,
    Int32,
    UInt32,
    Int64,
    UInt64,
    Binary,
    Clock,
}

const ABSENT: &[Absent] = &[
    Absent::Float32,
    Absent::Int8,
    Absent::UInt8,
    Absent::Int16,
    Absent::UInt16,
    Absent::Int32,
    Absent::UInt32,
    Absent::Int64,
    Absent::UInt64,
    Absent::Binary,
    Absent::Clock,
];

/// The clock interval and shift functions (no clocks: any reference is refused).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Timing {
    GetIntervalDecimal,
    GetIntervalFraction,
    GetShiftDecimal,
    GetShiftFraction,
    SetIntervalDecimal,
    SetIntervalFraction,
    SetShiftDecimal,
    SetShiftFraction,
}

const TIMING: &[Timing] = &[
    Timing::GetIntervalDecimal,
    Timing::GetIntervalFraction,
    Timing::GetShiftDecimal,
    Timing::GetShiftFraction,
    Timing::SetIntervalDecimal,
    Timing::SetIntervalFraction,
    Timing::SetShiftDecimal,
    Timing::SetShiftFraction,
];

/// The Model Exchange functions that fill an array of the states' (or indicators') size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StateArray {
    ContinuousStates,
    Derivatives,
    Nominals,
    EventIndicators,
}

/// One FMI 3.0 call. `inst` indexes the host's instance slots (an empty slot passes NULL);
/// every array passed holds the count announced with it (`nValues`, `nSeed`, ...), whether
/// that count fits the variables or not.
#[derive(Debug, Clone, PartialEq)]
pub enum Op3 {
    GetVersion,
    Instantiate {
        inst: usize,
        interface: Interface3,
        /// 0: a name, 1: empty, 2: NULL.
        name: u8,
        /// 0: the instantiation token, 1: FMI 2.0's GUID, 2: NULL, 3: another token.
        token: u8,
        /// 0: the resource folder's path, 1: NULL, 2: garbage, 3: its file: URI, 4: empty,
        /// 5: the path without its trailing slash.
        resources: u8,
        /// Whether `logMessage` is given (NULL is allowed: the FMU then logs nothing).
        logger: bool,
        logging: bool,
        visible: bool,
        /// Co-simulation's eventModeUsed (refused: no event mode) and earlyReturnAllowed.
        event_mode: bool,
        early_return: bool,
        /// Co-simulation's requiredIntermediateVariables: 0 none, 1 four references, 2 NULL
        /// with a count of four.
        required: u8,
        /// Whether the intermediateUpdate (or scheduled execution's) callbacks are given;
        /// they must never be called.
        callbacks: bool,
    },
    FreeInstance {
        inst: usize,
    },
    SetDebugLogging {
        inst: usize,
        on: bool,
        categories: Vec<Option<&'static str>>,
        arr: Arr,
    },
    EnterInitializationMode {
        inst: usize,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    },
    Plain {
        inst: usize,
        call: Plain,
    },
    GetFloat64 {
        inst: usize,
        vrs: Vec<u32>,
        n: usize,
        arr: Arr,
    },
    SetFloat64 {
        inst: usize,
        vrs: Vec<u32>,
        values: Vec<f64>,
        arr: Arr,
    },
    GetBoolean {
        inst: usize,
        vrs: Vec<u32>,
        n: usize,
        arr: Arr,
    },
    SetBoolean {
        inst: usize,
        vrs: Vec<u32>,
        values: Vec<bool>,
        arr: Arr,
    },
    GetString {
        inst: usize,
        vrs: Vec<u32>,
        n: usize,
        arr: Arr,
    },
    SetString {
        inst: usize,
        vrs: Vec<u32>,
        values: Vec<Str>,
        arr: Arr,
    },
    /// The getter (`set` false) or setter of a type the FMU has no variable of, with `n`
    /// values (Clock: one per reference).
    Absent {
        inst: usize,
        ty: Absent,
        set: bool,
        vrs: Vec<u32>,
        n: usize,
        arr: Arr,
    },
    ClockTiming {
        inst: usize,
        call: Timing,
        vrs: Vec<u32>,
        arr: Arr,
    },
    /// fmi3GetNumberOfVariableDependencies (`list` false) or fmi3GetVariableDependencies
    /// with arrays of `n`.
    VariableDependencies {
        inst: usize,
        list: bool,
        vr: u32,
        n: usize,
        null: bool,
    },
    GetFMUState {
        inst: usize,
        slot: usize,
        null_slot: bool,
    },
    SetFMUState {
        inst: usize,
        state: StateRef,
    },
    FreeFMUState {
        inst: usize,
        state: StateRef,
        null_slot: bool,
    },
    SerializedFMUStateSize {
        inst: usize,
        state: StateRef,
        null_size: bool,
    },
    SerializeFMUState {
        inst: usize,
        state: StateRef,
        buffer: usize,
        size_delta: i8,
        null: bool,
    },
    DeserializeFMUState {
        inst: usize,
        buffer: usize,
        corrupt: Corrupt,
        slot: usize,
        arr: Arr,
    },
    /// fmi3GetDirectionalDerivative or (`adjoint`) fmi3GetAdjointDerivative; `seed` holds
    /// nSeed values.
    Derivative {
        inst: usize,
        adjoint: bool,
        unknowns: Vec<u32>,
        knowns: Vec<u32>,
        seed: Vec<f64>,
        n_sensitivity: usize,
        /// Which of the four arrays is NULL (0: none).
        null: u8,
    },
    /// Bit i of `null`: the i-th output argument is NULL.
    UpdateDiscreteStates {
        inst: usize,
        null: u8,
    },
    CompletedIntegratorStep {
        inst: usize,
        no_set_prior: bool,
        null: u8,
    },
    SetTime {
        inst: usize,
        t: Time,
    },
    SetContinuousStates {
        inst: usize,
        x: Vec<f64>,
        null: bool,
    },
    GetStateArray {
        inst: usize,
        call: StateArray,
        n: usize,
        null: bool,
    },
    /// fmi3GetNumberOfContinuousStates (`states`) or fmi3GetNumberOfEventIndicators.
    GetNumberOf {
        inst: usize,
        states: bool,
        null: bool,
    },
    GetOutputDerivatives {
        inst: usize,
        vrs: Vec<u32>,
        orders: Vec<i32>,
        n: usize,
        arr: Arr,
    },
    DoStep {
        inst: usize,
        t: Time,
        h: f64,
        no_set_prior: bool,
        /// Bit i: the i-th output argument is NULL.
        null: u8,
    },
    ActivateModelPartition {
        inst: usize,
        clock: u32,
        t: f64,
    },
}

impl Op3 {
    /// The instance slot the call is given, if it takes one.
    pub fn inst(&self) -> Option<usize> {
        match *self {
            Op3::GetVersion => None,
            Op3::Instantiate { inst, .. }
            | Op3::FreeInstance { inst }
            | Op3::SetDebugLogging { inst, .. }
            | Op3::EnterInitializationMode { inst, .. }
            | Op3::Plain { inst, .. }
            | Op3::GetFloat64 { inst, .. }
            | Op3::SetFloat64 { inst, .. }
            | Op3::GetBoolean { inst, .. }
            | Op3::SetBoolean { inst, .. }
            | Op3::GetString { inst, .. }
            | Op3::SetString { inst, .. }
            | Op3::Absent { inst, .. }
            | Op3::ClockTiming { inst, .. }
            | Op3::VariableDependencies { inst, .. }
            | Op3::GetFMUState { inst, .. }
            | Op3::SetFMUState { inst, .. }
            | Op3::FreeFMUState { inst, .. }
            | Op3::SerializedFMUStateSize { inst, .. }
            | Op3::SerializeFMUState { inst, .. }
            | Op3::DeserializeFMUState { inst, .. }
            | Op3::Derivative { inst, .. }
            | Op3::UpdateDiscreteStates { inst, .. }
            | Op3::CompletedIntegratorStep { inst, .. }
            | Op3::SetTime { inst, .. }
            | Op3::SetContinuousStates { inst, .. }
            | Op3::GetStateArray { inst, .. }
            | Op3::GetNumberOf { inst, .. }
            | Op3::GetOutputDerivatives { inst, .. }
            | Op3::DoStep { inst, .. }
            | Op3::ActivateModelPartition { inst, .. } => Some(inst),
        }
    }

    /// The state-machine call, if this is one.
    fn transition(&self) -> Option<Transition> {
        match *self {
            Op3::EnterInitializationMode { .. } => Some(Transition::EnterInitializationMode),
            Op3::Plain { call, .. } => match call {
                Plain::ExitInitializationMode => Some(Transition::ExitInitializationMode),
                Plain::EnterContinuousTimeMode => Some(Transition::EnterContinuousTimeMode),
                Plain::EnterEventMode => Some(Transition::EnterEventMode),
                Plain::Terminate => Some(Transition::Terminate),
                Plain::Reset => Some(Transition::Reset),
                _ => None,
            },
            _ => None,
        }
    }
}

impl Generator {
    /// Value references of `pool`, each with chance `unknown` one of no variable.
    fn vrs3(&mut self, pool: &[u32], unknown: f64) -> Vec<u32> {
        self.pick_vrs(pool, unknown, UNKNOWN)
    }

    /// The values `vrs` hold (an unknown reference counted as one), or with chance `wrong`
    /// another count.
    fn n_values(&mut self, vrs: &[u32], wrong: f64) -> usize {
        let total: usize = vrs
            .iter()
            .map(|vr| self.v3.var(*vr).map_or(1, |v| v.size))
            .sum();
        if self.rng.chance(wrong) {
            self.rng
                .pick(&[total + 1, total.saturating_sub(1), 0, total + 13, 1, 9, 14])
        } else {
            total
        }
    }

    /// The elements of the coefficient array `vr`: near the start values, farther off, or
    /// with hostile elements.
    fn array_values(&mut self, vr: u32) -> Vec<f64> {
        let v3: &'static Vars3 = self.v3;
        let starts: &[f64] = v3.var(vr).map_or(&[], |v| &v.starts);
        let style = self.rng.below(10);
        starts
            .iter()
            .map(|&s| match style {
                0..=3 => s * (1.0 + self.rng.uniform(-0.02, 0.02)),
                4..=6 => s * self.rng.uniform(0.5, 1.5) + self.rng.uniform(-0.1, 0.1),
                _ if self.rng.chance(0.3) => self.rng.pick(HOSTILE),
                _ => s,
            })
            .collect()
    }

    /// fmi3SetFloat64 of some of `pool`, `nValues` right or (chance `wrong`) not.
    fn set_float64(&mut self, inst: usize, pool: &[u32], wrong: f64, arr: Arr) -> Op3 {
        let vrs = self.vrs3(pool, if wrong > 0.1 { 0.1 } else { 0.03 });
        let n = self.n_values(&vrs, wrong);
        let mut values = Vec::with_capacity(n);
        for &vr in &vrs {
            if self.v3.var(vr).is_some_and(|v| v.size > 1) {
                let elements = self.array_values(vr);
                values.extend(elements);
            } else {
                let v = self.real_value(vr);
                values.push(v);
            }
        }
        while values.len() < n {
            let v = self.rng.uniform(-10.0, 10.0);
            values.push(v);
        }
        values.truncate(n);
        Op3::SetFloat64 {
            inst,
            vrs,
            values,
            arr,
        }
    }

    fn get_float64(&mut self, inst: usize, pool: &[u32], wrong: f64, arr: Arr) -> Op3 {
        let vrs = self.vrs3(pool, if wrong > 0.1 { 0.1 } else { 0.03 });
        let n = self.n_values(&vrs, wrong);
        Op3::GetFloat64 { inst, vrs, n, arr }
    }

    fn instantiate3(&mut self, inst: usize, hostile: bool) -> Op3 {
        let interface = if hostile && self.rng.chance(0.05) {
            Interface3::ScheduledExecution
        } else if self.rng.chance(0.5) {
            Interface3::ModelExchange
        } else {
            Interface3::CoSimulation
        };
        Op3::Instantiate {
            inst,
            interface,
            name: self.bad(hostile, 3),
            token: self.bad(hostile, 4),
            resources: self.bad(hostile, 6),
            logger: !self.rng.chance(if hostile { 0.2 } else { 0.1 }),
            logging: self.rng.chance(0.5),
            visible: self.rng.chance(0.5),
            event_mode: hostile && self.rng.chance(0.1),
            early_return: self.rng.chance(0.3),
            required: if hostile && self.rng.chance(0.1) {
                1 + self.rng.below(2) as u8
            } else {
                0
            },
            callbacks: self.rng.chance(0.3),
        }
    }

    fn continuous_states(&mut self, inst: usize, hostile: bool) -> Op3 {
        let n = if hostile {
            self.count()
        } else {
            self.v3.n_states
        };
        let x = self.hostile_values(n, 0.2, -1.5, 1.5);
        Op3::SetContinuousStates {
            inst,
            x,
            null: hostile && self.rng.chance(0.05),
        }
    }

    /// A directional or adjoint derivative: of outputs and state derivatives with respect to
    /// inputs and states, now and then of or with respect to arrays, parameters, time or
    /// variables of another type; `nSeed` and `nSensitivity` right or not.
    fn derivative3(&mut self, inst: usize, hostile: bool) -> Op3 {
        let v = self.v3;
        let mut unknown_pool: Vec<u32> = v.outputs.iter().chain(&v.derivatives).copied().collect();
        let mut known_pool = v.inputs_all.clone();
        known_pool.extend(&v.states);
        if self.rng.chance(if hostile { 0.5 } else { 0.1 }) {
            let odd: Vec<u32> = v
                .arrays
                .iter()
                .chain(&v.parameters)
                .chain(&v.booleans)
                .chain(&v.strings)
                .chain(std::iter::once(&v.time))
                .copied()
                .collect();
            unknown_pool.extend(&odd);
            unknown_pool.extend(&v.inputs);
            known_pool.extend(&odd);
            known_pool.extend(&v.outputs);
        }
        let unknown_chance = if hostile { 0.1 } else { 0.03 };
        let unknowns = self.vrs3(&unknown_pool, unknown_chance);
        let knowns = self.vrs3(&known_pool, unknown_chance);
        let adjoint = self.rng.chance(0.5);
        let (mut n_seed, mut n_sensitivity) = if adjoint {
            (unknowns.len(), knowns.len())
        } else {
            (knowns.len(), unknowns.len())
        };
        if self.rng.chance(if hostile { 0.3 } else { 0.05 }) {
            let wrong = |g: &mut Generator, n: usize| {
                g.rng.pick(&[n + 1, n.saturating_sub(1), 0, n + 14, 1, 3])
            };
            match self.rng.below(3) {
                0 => n_seed = wrong(self, n_seed),
                1 => n_sensitivity = wrong(self, n_sensitivity),
                _ => {
                    // The counts of the other function (adjoint for directional, ...).
                    std::mem::swap(&mut n_seed, &mut n_sensitivity);
                }
            }
        }
        let seed = self.hostile_values(n_seed, 0.15, -2.0, 2.0);
        let null = self.null_of_four();
        Op3::Derivative {
            inst,
            adjoint,
            unknowns,
            knowns,
            seed,
            n_sensitivity,
            null,
        }
    }

    /// A slot or buffer, mostly one of `good` (when there is one), else any.
    fn prefer(&mut self, good: impl Fn(&Generator, usize) -> bool) -> usize {
        let good: Vec<usize> = (0..STATE_SLOTS).filter(|s| good(self, *s)).collect();
        if !good.is_empty() && self.rng.chance(0.8) {
            self.rng.pick(&good)
        } else {
            self.rng.below(STATE_SLOTS)
        }
    }

    /// Saving, restoring, serializing and reading back FMU states: mostly with the slots
    /// expected to hold this instance's states and the buffers expected to hold a state.
    fn state_op3(&mut self, inst: usize) -> Op3 {
        let mine = move |g: &Generator, s: usize| g.held[s] == Some(inst);
        let free_or_mine = move |g: &Generator, s: usize| g.held[s].is_none_or(|i| i == inst);
        match self.rng.below(6) {
            0 | 1 => Op3::GetFMUState {
                inst,
                slot: self.prefer(free_or_mine),
                null_slot: false,
            },
            2 => Op3::SetFMUState {
                inst,
                state: StateRef::Slot(self.prefer(mine)),
            },
            3 => {
                let slot = self.prefer(mine);
                Op3::SerializeFMUState {
                    inst,
                    state: StateRef::Slot(slot),
                    buffer: self.rng.below(STATE_SLOTS),
                    size_delta: 0,
                    null: false,
                }
            }
            4 => Op3::DeserializeFMUState {
                inst,
                buffer: self.prefer(|g, b| g.filled[b]),
                corrupt: self.corrupt(),
                slot: self.prefer(free_or_mine),
                arr: Arr::Ok,
            },
            _ => Op3::FreeFMUState {
                inst,
                state: StateRef::Slot(self.prefer(mine)),
                null_slot: false,
            },
        }
    }

    fn plain(inst: usize, call: Plain) -> Op3 {
        Op3::Plain { inst, call }
    }

    /// A call that fits the FMI 3.0 state the instance `inst` is expected to be in.
    pub(crate) fn guided3(&mut self, inst: usize, r: usize) -> Op3 {
        let v: &'static Vars3 = self.v3;
        let all = &v.float64;
        match self.expect[inst] {
            Expect::Free => self.instantiate3(inst, false),
            Expect::Instantiated { me } => match r {
                0..=24 => Op3::SetString {
                    inst,
                    vrs: v.strings.clone(),
                    values: vec![self.string_value()],
                    arr: Arr::Ok,
                },
                25..=44 => self.set_float64(inst, &v.parameter_pool, 0.1, Arr::Ok),
                45..=49 => Op3::SetBoolean {
                    inst,
                    vrs: v.booleans.clone(),
                    values: vec![self.rng.chance(0.5)],
                    arr: Arr::Ok,
                },
                50..=59 => self.set_float64(inst, &v.inputs_speed, 0.02, Arr::Ok),
                60..=64 => self.state_op3(inst),
                65..=66 => Op3::GetNumberOf {
                    inst,
                    states: self.rng.chance(0.5),
                    null: false,
                },
                67..=69 if me => Op3::GetStateArray {
                    inst,
                    call: StateArray::Nominals,
                    n: v.n_states,
                    null: false,
                },
                _ => {
                    let (tolerance, start, stop) = self.experiment(false);
                    Op3::EnterInitializationMode {
                        inst,
                        tolerance,
                        start,
                        stop,
                    }
                }
            },
            Expect::Init { me } => match r {
                0..=14 => self.set_float64(inst, &v.inputs_all, 0.02, Arr::Ok),
                15..=19 => self.set_float64(inst, &v.parameter_pool, 0.1, Arr::Ok),
                20..=29 => self.get_float64(inst, all, 0.02, Arr::Ok),
                30..=39 => self.derivative3(inst, false),
                40..=44 if me => Op3::GetStateArray {
                    inst,
                    call: StateArray::ContinuousStates,
                    n: v.n_states,
                    null: false,
                },
                45..=49 => self.state_op3(inst),
                _ => Self::plain(inst, Plain::ExitInitializationMode),
            },
            Expect::Step => match r {
                0..=34 => Op3::DoStep {
                    inst,
                    t: Time::Current,
                    h: self.step_size(),
                    no_set_prior: self.rng.chance(0.5),
                    null: 0,
                },
                35..=49 => self.set_float64(inst, &v.inputs_all, 0.02, Arr::Ok),
                50..=59 => self.get_float64(inst, all, 0.02, Arr::Ok),
                60..=67 => self.derivative3(inst, false),
                68..=84 => self.state_op3(inst),
                85..=87 => Op3::GetBoolean {
                    inst,
                    vrs: v.booleans.clone(),
                    n: 1,
                    arr: Arr::Ok,
                },
                88..=89 => Op3::GetString {
                    inst,
                    vrs: v.strings.clone(),
                    n: 1,
                    arr: Arr::Ok,
                },
                90..=94 => Self::plain(inst, Plain::Terminate),
                95..=97 => Self::plain(inst, Plain::Reset),
                _ => Op3::FreeInstance { inst },
            },
            Expect::Event => match r {
                0..=34 => Self::plain(inst, Plain::EnterContinuousTimeMode),
                35..=44 => Op3::UpdateDiscreteStates { inst, null: 0 },
                45..=49 => Self::plain(inst, Plain::EvaluateDiscreteStates),
                50..=64 => self.set_float64(inst, &v.inputs_speed, 0.02, Arr::Ok),
                65..=79 => self.state_op3(inst),
                80..=89 => self.get_float64(inst, all, 0.02, Arr::Ok),
                90..=95 => Self::plain(inst, Plain::Terminate),
                _ => Self::plain(inst, Plain::Reset),
            },
            Expect::Continuous => match r {
                0..=9 => Op3::SetTime {
                    inst,
                    t: Time::Value(self.rng.uniform(0.0, 10.0)),
                },
                10..=24 => self.continuous_states(inst, false),
                25..=39 => Op3::GetStateArray {
                    inst,
                    call: StateArray::Derivatives,
                    n: v.n_states,
                    null: false,
                },
                40..=44 => Op3::GetStateArray {
                    inst,
                    call: StateArray::ContinuousStates,
                    n: v.n_states,
                    null: false,
                },
                45..=54 => self.derivative3(inst, false),
                55..=59 => Op3::CompletedIntegratorStep {
                    inst,
                    no_set_prior: self.rng.chance(0.5),
                    null: 0,
                },
                60..=72 => self.set_float64(inst, &v.inputs_all, 0.02, Arr::Ok),
                73..=84 => self.state_op3(inst),
                85..=89 => self.get_float64(inst, all, 0.02, Arr::Ok),
                90..=93 => Self::plain(inst, Plain::EnterEventMode),
                94..=96 => Op3::GetStateArray {
                    inst,
                    call: StateArray::Nominals,
                    n: v.n_states,
                    null: false,
                },
                97 => Op3::GetStateArray {
                    inst,
                    call: StateArray::EventIndicators,
                    n: v.n_indicators,
                    null: false,
                },
                _ => Self::plain(inst, Plain::Terminate),
            },
            Expect::Terminated { .. } => match r {
                0..=29 => self.get_float64(inst, all, 0.02, Arr::Ok),
                30..=49 => self.derivative3(inst, false),
                50..=64 => self.state_op3(inst),
                65..=84 => Self::plain(inst, Plain::Reset),
                _ => Op3::FreeInstance { inst },
            },
        }
    }

    /// `pool` with chance `p`, else the references of every variable and of none.
    fn or_every(&mut self, pool: &'static [u32], p: f64) -> &'static [u32] {
        if self.rng.chance(p) {
            pool
        } else {
            &self.v3.every
        }
    }

    /// References (mostly of `pool`), `nValues` and arrays of a random getter or setter.
    fn typed_args(&mut self, pool: &'static [u32]) -> (Vec<u32>, usize, Arr) {
        let pool = self.or_every(pool, 0.6);
        let vrs = self.vrs3(pool, 0.1);
        let n = self.n_values(&vrs, 0.3);
        (vrs, n, self.arr())
    }

    /// Any FMI 3.0 call, any arguments.
    pub(crate) fn random3(&mut self) -> Op3 {
        let inst = self.rng.below(INSTANCES);
        let v: &'static Vars3 = self.v3;
        // Value references of every type, and of none.
        let every = &v.every;
        match self.rng.below(40) {
            0 => Op3::GetVersion,
            1 => self.instantiate3(inst, true),
            2 => Op3::FreeInstance { inst },
            3 => {
                let (on, categories, arr) = self.debug_logging();
                Op3::SetDebugLogging {
                    inst,
                    on,
                    categories,
                    arr,
                }
            }
            4 => {
                let (tolerance, start, stop) = self.experiment(true);
                Op3::EnterInitializationMode {
                    inst,
                    tolerance,
                    start,
                    stop,
                }
            }
            5..=8 => Self::plain(inst, self.rng.pick(PLAIN)),
            9 => {
                let pool = self.or_every(&v.float64, 0.8);
                let arr = self.arr();
                self.get_float64(inst, pool, 0.3, arr)
            }
            10 => {
                let pool = self.or_every(&v.float64, 0.8);
                let arr = self.arr();
                self.set_float64(inst, pool, 0.3, arr)
            }
            11 | 12 => {
                let (vrs, n, arr) = self.typed_args(&v.booleans);
                if self.rng.chance(0.5) {
                    Op3::GetBoolean { inst, vrs, n, arr }
                } else {
                    let values = (0..n).map(|_| self.rng.chance(0.5)).collect();
                    Op3::SetBoolean {
                        inst,
                        vrs,
                        values,
                        arr,
                    }
                }
            }
            13 | 14 => {
                let (vrs, n, arr) = self.typed_args(&v.strings);
                if self.rng.chance(0.5) {
                    Op3::GetString { inst, vrs, n, arr }
                } else {
                    let values = (0..n).map(|_| self.string_value()).collect();
                    Op3::SetString {
                        inst,
                        vrs,
                        values,
                        arr,
                    }
                }
            }
            15..=18 => {
                let vrs = self.vrs3(every, 0.3);
                let n = if self.rng.chance(0.7) {
                    vrs.len()
                } else {
                    self.rng.pick(&[0, 1, 14])
                };
                Op3::Absent {
                    inst,
                    ty: self.rng.pick(ABSENT),
                    set: self.rng.chance(0.5),
                    vrs,
                    n,
                    arr: self.arr(),
                }
            }
            19 | 20 => Op3::ClockTiming {
                inst,
                call: self.rng.pick(TIMING),
                vrs: self.vrs3(every, 0.3),
                arr: self.arr(),
            },
            21 => Op3::VariableDependencies {
                inst,
                list: self.rng.chance(0.5),
                vr: self.rng.pick(every),
                n: self.rng.pick(&[0, 1, 3, 8]),
                null: self.rng.chance(0.1),
            },
            k @ 22..=27 => random_state_op!(self, inst, k - 22, Op3:
                GetFMUState, SetFMUState, FreeFMUState,
                SerializedFMUStateSize, SerializeFMUState, DeserializeFMUState),
            28 | 29 => self.derivative3(inst, true),
            30 => Op3::UpdateDiscreteStates {
                inst,
                null: if self.rng.chance(0.3) {
                    self.rng.below(64) as u8
                } else {
                    0
                },
            },
            31 => Op3::CompletedIntegratorStep {
                inst,
                no_set_prior: self.rng.chance(0.5),
                null: self.rng.below(4) as u8,
            },
            32 => Op3::SetTime {
                inst,
                t: self.time(),
            },
            33 => self.continuous_states(inst, true),
            34 | 35 => Op3::GetStateArray {
                inst,
                call: self.rng.pick(&[
                    StateArray::ContinuousStates,
                    StateArray::Derivatives,
                    StateArray::Nominals,
                    StateArray::EventIndicators,
                ]),
                n: self.rng.pick(&[3, 3, 3, 0, 0, 2, 4]),
                null: self.rng.chance(0.05),
            },
            36 => Op3::GetNumberOf {
                inst,
                states: self.rng.chance(0.5),
                null: self.rng.chance(0.1),
            },
            37 => {
                let vrs = self.vrs3(&v.outputs, 0.1);
                let orders = vrs
                    .iter()
                    .map(|_| self.rng.pick(&[1, 1, 0, 2, -1]))
                    .collect();
                Op3::GetOutputDerivatives {
                    inst,
                    n: vrs.len(),
                    vrs,
                    orders,
                    arr: self.arr(),
                }
            }
            38 => Op3::DoStep {
                inst,
                t: self.time(),
                h: self.step_size(),
                no_set_prior: self.rng.chance(0.5),
                null: if self.rng.chance(0.3) {
                    self.rng.below(16) as u8
                } else {
                    0
                },
            },
            _ => Op3::ActivateModelPartition {
                inst,
                clock: self.rng.pick(every),
                t: self.hostile_or(0.5, 0.0, 10.0),
            },
        }
    }

    /// Where `op` takes its instance, if it succeeds (calls on an instance of the other
    /// standard are refused and change nothing).
    pub(crate) fn track3(&mut self, op: &Op3) {
        match *op {
            Op3::Instantiate {
                inst,
                interface,
                name,
                token,
                event_mode,
                ..
            } => {
                let made = name == 0
                    && token == 0
                    && match interface {
                        Interface3::ModelExchange => true,
                        Interface3::CoSimulation => !event_mode,
                        Interface3::ScheduledExecution => false,
                    };
                let me = made.then_some(interface == Interface3::ModelExchange);
                self.instantiated(inst, me, true);
                return;
            }
            Op3::FreeInstance { inst } => {
                self.freed(inst);
                return;
            }
            _ => {}
        }
        let Some(inst) = op.inst() else { return };
        if !self.fmi3[inst] || self.expect[inst] == Expect::Free {
            return;
        }
        match *op {
            Op3::GetFMUState {
                slot,
                null_slot: false,
                ..
            } if self.held[slot].is_none() => self.held[slot] = Some(inst),
            Op3::FreeFMUState {
                state: StateRef::Slot(slot),
                null_slot: false,
                ..
            } if self.held[slot] == Some(inst) => self.held[slot] = None,
            Op3::SerializeFMUState {
                state: StateRef::Slot(slot),
                buffer,
                size_delta: 0,
                null: false,
                ..
            } if self.held[slot] == Some(inst) => self.filled[buffer] = true,
            Op3::DeserializeFMUState {
                buffer,
                corrupt: Corrupt::None,
                slot,
                arr: Arr::Ok,
                ..
            } if self.filled[buffer] && self.held[slot].is_none() => self.held[slot] = Some(inst),
            _ => {}
        }
        if let Some(t) = op.transition() {
            self.expect[inst] = self.expect[inst].after(t);
        }
    }
}
