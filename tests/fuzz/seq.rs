//! Call sequences: the operations ([`Op`], one FMI call with its arguments each) and their
//! generation from a seed. Part of the time the generator follows the state machine of the
//! instance it picks (as it expects it to be), so that sequences get deep: instantiated with
//! resources, a parameter file, initialized, stepping or in continuous-time mode, with FMU
//! states saved, restored, serialized and read back. The rest is any call with any
//! arguments: NaN, infinities, huge, denormal and negative values, unknown value references,
//! NULL arrays, wrong states, corrupted serialized states, hostile parameter files.
//!
//! A seed's [`Mode`] says which standard its sequence uses: FMI 2.0 alone (the calls of this
//! file), FMI 3.0 alone (seq3.rs), or both at once, each instance driven by the standard that
//! made it and hostile calls of either standard given to any instance.
//!
//! What both standards share is here: the hostile values and arguments, the FMU-state calls,
//! the state machine ([`Expect`], [`Transition`]).

use pacejka87_tire::variables::REAL_VARIABLES;

use crate::seq3::{Op3, Vars3};

/// Instances a sequence juggles at once.
pub const INSTANCES: usize = 3;
/// FMU-state slots of the host (shared by all instances: a state may go to another).
pub const STATE_SLOTS: usize = 4;

/// Which standard a sequence uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// FMI 2.0 calls only; the generator draws nothing for FMI 3.0 in these sequences.
    Fmi2,
    /// FMI 3.0 calls, and a few FMI 2.0 calls given to the FMI 3.0 instances.
    Fmi3,
    /// Instances of both standards, calls of both given to either.
    Mixed,
}

impl Mode {
    /// Seeds 0 and 1 modulo 5 are FMI 2.0, 2 and 3 FMI 3.0, 4 mixed.
    pub fn of(seed: u64) -> Mode {
        match seed % 5 {
            0 | 1 => Mode::Fmi2,
            2 | 3 => Mode::Fmi3,
            _ => Mode::Mixed,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Mode::Fmi2 => "FMI 2.0",
            Mode::Fmi3 => "FMI 3.0",
            Mode::Mixed => "mixed",
        }
    }
}

/// xorshift64*: small, fast, and the same on every platform.
#[derive(Clone)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03 | 1)
    }
    pub fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    pub fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }
    pub fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    pub fn pick<T: Copy>(&mut self, items: &[T]) -> T {
        items[self.below(items.len())]
    }
}

/// Values that break naive code.
pub const HOSTILE: &[f64] = &[
    f64::NAN,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::MAX,
    -f64::MAX,
    1.7e308,
    -1.7e308,
    5e-324,
    -5e-324,
    2.2250738585072014e-308,
    0.0,
    -0.0,
    1e-300,
    1e300,
    -1e300,
    -1.0,
    1e9,
    -1e9,
    4.9e-300,
];

/// An array argument: as it should be, or NULL (with its length still announced).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Arr {
    Ok,
    /// The first array argument is NULL.
    Null1,
    /// The second array argument is NULL.
    Null2,
}

impl Arr {
    /// `p`, or NULL when this is `which` (the argument it makes NULL).
    pub fn ptr<T>(self, which: Arr, p: *const T) -> *const T {
        if self == which { std::ptr::null() } else { p }
    }

    /// As [`Arr::ptr`], for an array the call writes.
    pub fn ptr_mut<T>(self, which: Arr, p: *mut T) -> *mut T {
        if self == which {
            std::ptr::null_mut()
        } else {
            p
        }
    }
}

/// A string argument of fmi2SetString.
#[derive(Debug, Clone, PartialEq)]
pub enum Str {
    Null,
    /// One of the prepared parameter files, by index (see `run::Files`).
    File(usize),
    Text(String),
    /// Bytes that are not UTF-8.
    NotUtf8,
}

/// Which FMU state a call passes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StateRef {
    /// The pointer in the host's slot (NULL if empty).
    Slot(usize),
    /// A pointer of that slot freed earlier (remembered by the host).
    Stale(usize),
    /// A pointer that points nowhere the FMU allocated.
    Garbage,
}

/// How a serialized state is damaged before fmi2DeSerializeFMUstate.
#[derive(Debug, Clone, PartialEq)]
pub enum Corrupt {
    None,
    /// Keeps only the first `n` permille of the bytes.
    Truncate(u16),
    /// XORs the byte at `at` permille of the length with `mask`.
    Flip {
        at: u16,
        mask: u8,
    },
    /// Replaces the `nth` number of the JSON text with `with`.
    Number {
        nth: u16,
        with: &'static str,
    },
    /// Replaces the `nth` quoted word with `with`.
    Word {
        nth: u16,
        with: &'static str,
    },
    /// Appends bytes.
    Append(&'static str),
    Empty,
}

/// The time argument of fmi2DoStep / fmi2SetTime.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Time {
    /// The instance's time as fmi2GetRealStatus(fmi2LastSuccessfulTime) says (else 0).
    Current,
    Value(f64),
}

/// One FMI call. `inst` indexes the host's instance slots (an empty slot passes NULL).
#[derive(Debug, Clone, PartialEq)]
pub enum Op {
    GetTypesPlatform,
    GetVersion,
    Instantiate {
        inst: usize,
        fmu_type: i32,
        /// 0: a name, 1: empty, 2: NULL.
        name: u8,
        /// 0: right GUID, 1: wrong, 2: NULL.
        guid: u8,
        /// 0: the resource folder's URI, 1: NULL, 2: a garbage URI, 3: a plain path.
        resources: u8,
        /// 0: complete, 1: NULL logger, 2: NULL allocateMemory, 3: NULL pointer.
        callbacks: u8,
        logging: bool,
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
    SetupExperiment {
        inst: usize,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    },
    EnterInitializationMode {
        inst: usize,
    },
    ExitInitializationMode {
        inst: usize,
    },
    Terminate {
        inst: usize,
    },
    Reset {
        inst: usize,
    },
    GetReal {
        inst: usize,
        vrs: Vec<u32>,
        arr: Arr,
    },
    GetInteger {
        inst: usize,
        vrs: Vec<u32>,
        arr: Arr,
    },
    GetBoolean {
        inst: usize,
        vrs: Vec<u32>,
        arr: Arr,
    },
    GetString {
        inst: usize,
        vrs: Vec<u32>,
        arr: Arr,
    },
    SetReal {
        inst: usize,
        vrs: Vec<u32>,
        values: Vec<f64>,
        arr: Arr,
    },
    SetInteger {
        inst: usize,
        vrs: Vec<u32>,
        values: Vec<i32>,
        arr: Arr,
    },
    SetBoolean {
        inst: usize,
        vrs: Vec<u32>,
        values: Vec<i32>,
        arr: Arr,
    },
    SetString {
        inst: usize,
        vrs: Vec<u32>,
        values: Vec<Str>,
        arr: Arr,
    },
    GetFMUstate {
        inst: usize,
        slot: usize,
        null_slot: bool,
    },
    SetFMUstate {
        inst: usize,
        state: StateRef,
    },
    FreeFMUstate {
        inst: usize,
        state: StateRef,
        null_slot: bool,
    },
    SerializedFMUstateSize {
        inst: usize,
        state: StateRef,
        null_size: bool,
    },
    /// Serializes into the host's buffer `buffer`, sized exactly (`size_delta` 0) or not.
    SerializeFMUstate {
        inst: usize,
        state: StateRef,
        buffer: usize,
        size_delta: i8,
        null: bool,
    },
    DeSerializeFMUstate {
        inst: usize,
        buffer: usize,
        corrupt: Corrupt,
        slot: usize,
        arr: Arr,
    },
    GetDirectionalDerivative {
        inst: usize,
        unknown: Vec<u32>,
        known: Vec<u32>,
        dv: Vec<f64>,
        /// Which of the four arrays is NULL (0: none).
        null: u8,
    },
    SetRealInputDerivatives {
        inst: usize,
    },
    GetRealOutputDerivatives {
        inst: usize,
    },
    DoStep {
        inst: usize,
        t: Time,
        h: f64,
    },
    CancelStep {
        inst: usize,
    },
    /// fmi2Get{,Real,Integer,Boolean,String}Status by `which` (0..5).
    GetStatus {
        inst: usize,
        which: u8,
        kind: i32,
        null: bool,
    },
    EnterEventMode {
        inst: usize,
    },
    NewDiscreteStates {
        inst: usize,
        null: bool,
    },
    EnterContinuousTimeMode {
        inst: usize,
    },
    CompletedIntegratorStep {
        inst: usize,
        null: bool,
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
    GetContinuousStates {
        inst: usize,
        n: usize,
        null: bool,
    },
    GetDerivatives {
        inst: usize,
        n: usize,
        null: bool,
    },
    GetNominalsOfContinuousStates {
        inst: usize,
        n: usize,
        null: bool,
    },
    GetEventIndicators {
        inst: usize,
        n: usize,
        null: bool,
    },
    /// An FMI 3.0 call.
    Fmi3(Op3),
}

impl Op {
    /// The instance slot the call is given, if it takes one.
    pub fn inst(&self) -> Option<usize> {
        match *self {
            Op::GetTypesPlatform | Op::GetVersion => None,
            Op::Fmi3(ref op) => op.inst(),
            Op::Instantiate { inst, .. }
            | Op::FreeInstance { inst }
            | Op::SetDebugLogging { inst, .. }
            | Op::SetupExperiment { inst, .. }
            | Op::EnterInitializationMode { inst }
            | Op::ExitInitializationMode { inst }
            | Op::Terminate { inst }
            | Op::Reset { inst }
            | Op::GetReal { inst, .. }
            | Op::GetInteger { inst, .. }
            | Op::GetBoolean { inst, .. }
            | Op::GetString { inst, .. }
            | Op::SetReal { inst, .. }
            | Op::SetInteger { inst, .. }
            | Op::SetBoolean { inst, .. }
            | Op::SetString { inst, .. }
            | Op::GetFMUstate { inst, .. }
            | Op::SetFMUstate { inst, .. }
            | Op::FreeFMUstate { inst, .. }
            | Op::SerializedFMUstateSize { inst, .. }
            | Op::SerializeFMUstate { inst, .. }
            | Op::DeSerializeFMUstate { inst, .. }
            | Op::GetDirectionalDerivative { inst, .. }
            | Op::SetRealInputDerivatives { inst }
            | Op::GetRealOutputDerivatives { inst }
            | Op::DoStep { inst, .. }
            | Op::CancelStep { inst }
            | Op::GetStatus { inst, .. }
            | Op::EnterEventMode { inst }
            | Op::NewDiscreteStates { inst, .. }
            | Op::EnterContinuousTimeMode { inst }
            | Op::CompletedIntegratorStep { inst, .. }
            | Op::SetTime { inst, .. }
            | Op::SetContinuousStates { inst, .. }
            | Op::GetContinuousStates { inst, .. }
            | Op::GetDerivatives { inst, .. }
            | Op::GetNominalsOfContinuousStates { inst, .. }
            | Op::GetEventIndicators { inst, .. } => Some(inst),
        }
    }
}

/// FMU-state call `$k` (0..6: get, set, free, size, serialize, deserialize) of a standard,
/// any arguments: `$op` and its variants of those (both standards have the same arguments).
macro_rules! random_state_op {
    ($g:expr, $inst:expr, $k:expr, $op:ident:
     $get:ident, $set:ident, $free:ident, $size:ident, $ser:ident, $de:ident) => {{
        let (g, inst): (&mut Generator, usize) = (&mut *$g, $inst);
        match $k {
            0 => $op::$get {
                inst,
                slot: g.rng.below(STATE_SLOTS),
                null_slot: g.rng.chance(0.05),
            },
            1 => $op::$set {
                inst,
                state: g.state_ref(),
            },
            2 => $op::$free {
                inst,
                state: g.state_ref(),
                null_slot: g.rng.chance(0.05),
            },
            3 => $op::$size {
                inst,
                state: g.state_ref(),
                null_size: g.rng.chance(0.05),
            },
            4 => $op::$ser {
                inst,
                state: g.state_ref(),
                buffer: g.rng.below(STATE_SLOTS),
                size_delta: g.rng.pick(&[0, 0, 0, -1, 1, -100, 100]),
                null: g.rng.chance(0.05),
            },
            _ => $op::$de {
                inst,
                buffer: g.rng.below(STATE_SLOTS),
                corrupt: g.corrupt(),
                slot: g.rng.below(STATE_SLOTS),
                arr: g.arr(),
            },
        }
    }};
}
pub(crate) use random_state_op;

/// The state-machine calls both standards have.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Transition {
    EnterInitializationMode,
    ExitInitializationMode,
    EnterContinuousTimeMode,
    EnterEventMode,
    Terminate,
    Reset,
}

impl Op {
    /// The instance slot and the state-machine call, if this is one.
    fn transition(&self) -> Option<(usize, Transition)> {
        Some(match *self {
            Op::EnterInitializationMode { inst } => (inst, Transition::EnterInitializationMode),
            Op::ExitInitializationMode { inst } => (inst, Transition::ExitInitializationMode),
            Op::EnterContinuousTimeMode { inst } => (inst, Transition::EnterContinuousTimeMode),
            Op::EnterEventMode { inst } => (inst, Transition::EnterEventMode),
            Op::Terminate { inst } => (inst, Transition::Terminate),
            Op::Reset { inst } => (inst, Transition::Reset),
            _ => return None,
        })
    }
}

/// The state the generator expects an instance to be in (FMI 3.0's StepMode is `Step`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Expect {
    Free,
    Instantiated { me: bool },
    Init { me: bool },
    Step,
    Event,
    Continuous,
    Terminated { me: bool },
}

impl Expect {
    /// The state after `t` succeeded in this one.
    pub(crate) fn after(self, t: Transition) -> Expect {
        match (t, self) {
            (Transition::EnterInitializationMode, Expect::Instantiated { me }) => {
                Expect::Init { me }
            }
            (Transition::ExitInitializationMode, Expect::Init { me }) => {
                if me {
                    Expect::Event
                } else {
                    Expect::Step
                }
            }
            (Transition::EnterContinuousTimeMode, Expect::Event) => Expect::Continuous,
            (Transition::EnterEventMode, Expect::Continuous) => Expect::Event,
            (Transition::Terminate, Expect::Step) => Expect::Terminated { me: false },
            (Transition::Terminate, Expect::Event | Expect::Continuous) => {
                Expect::Terminated { me: true }
            }
            (Transition::Reset, Expect::Step) => Expect::Instantiated { me: false },
            (Transition::Reset, Expect::Event | Expect::Continuous) => {
                Expect::Instantiated { me: true }
            }
            (
                Transition::Reset,
                Expect::Instantiated { me } | Expect::Init { me } | Expect::Terminated { me },
            ) => Expect::Instantiated { me },
            (_, other) => other,
        }
    }
}

/// What a variable is, as the fuzzer sees it (from its name in the generated table).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Kind {
    Input,
    Speed,
    Condition,
    Output,
    Parameter,
    Local,
}

fn kind(name: &str) -> Kind {
    match name {
        "Fz" | "alpha" | "kappa" | "gamma" => Kind::Input,
        "vx" => Kind::Speed,
        "p" | "T_tread" => Kind::Condition,
        "Fx" | "Fy" | "Mz" => Kind::Output,
        n if n.starts_with("lag_") || n.starts_with("der(") => Kind::Local,
        _ => Kind::Parameter,
    }
}

fn vrs_of(k: Kind) -> Vec<u32> {
    // Each variable's kind, worked out once per process (a generator per sequence needs them).
    static KINDS: std::sync::OnceLock<Vec<(Kind, u32)>> = std::sync::OnceLock::new();
    KINDS
        .get_or_init(|| {
            REAL_VARIABLES
                .iter()
                .map(|v| (kind(v.name), v.vr))
                .collect()
        })
        .iter()
        .filter(|(kind, _)| *kind == k)
        .map(|(_, vr)| *vr)
        .collect()
}

/// Generates sequences.
pub struct Generator {
    pub(crate) rng: Rng,
    pub(crate) mode: Mode,
    pub(crate) expect: [Expect; INSTANCES],
    /// Whether the instance expected in a slot is an FMI 3.0 one.
    pub(crate) fmi3: [bool; INSTANCES],
    /// FMI 3.0: the instance whose state each FMU-state slot is expected to hold, and whether
    /// each serialized buffer is expected to hold a state (the guided calls use them).
    pub(crate) held: [Option<usize>; STATE_SLOTS],
    pub(crate) filled: [bool; STATE_SLOTS],
    pub(crate) v3: &'static Vars3,
    all_real: Vec<u32>,
    inputs: Vec<u32>,
    speed: u32,
    conditions: Vec<u32>,
    outputs: Vec<u32>,
    parameters: Vec<u32>,
    locals: Vec<u32>,
    /// How many parameter files `run::Files` prepares (good ones first).
    files: usize,
    good_files: usize,
}

impl Generator {
    pub fn new(seed: u64, files: usize, good_files: usize) -> Generator {
        Generator {
            rng: Rng::new(seed),
            mode: Mode::of(seed),
            expect: [Expect::Free; INSTANCES],
            fmi3: [false; INSTANCES],
            held: [None; STATE_SLOTS],
            filled: [false; STATE_SLOTS],
            v3: Vars3::get(),
            all_real: REAL_VARIABLES.iter().map(|v| v.vr).collect(),
            inputs: vrs_of(Kind::Input),
            speed: vrs_of(Kind::Speed)[0],
            conditions: vrs_of(Kind::Condition),
            outputs: vrs_of(Kind::Output),
            parameters: vrs_of(Kind::Parameter),
            locals: vrs_of(Kind::Local),
            files,
            good_files,
        }
    }

    /// The sequence of seed `seed`: 1 to 120 calls.
    pub fn sequence(seed: u64, files: usize, good_files: usize) -> Vec<Op> {
        let mut g = Generator::new(seed, files, good_files);
        let n = 1 + g.rng.below(120);
        // How strictly this sequence follows the state machine.
        let guided = g.rng.pick(&[0.0, 0.6, 0.85, 0.95]);
        (0..n)
            .map(|_| {
                if g.rng.chance(guided) {
                    g.guided()
                } else {
                    g.random()
                }
            })
            .collect()
    }

    pub(crate) fn real_value(&mut self, vr: u32) -> f64 {
        if self.rng.chance(0.25) {
            return self.rng.pick(HOSTILE);
        }
        if self.rng.chance(0.05) {
            // Anything from denormal to huge, either sign.
            let e = self.rng.uniform(-320.0, 308.0);
            return if self.rng.chance(0.5) { 1.0 } else { -1.0 } * 10f64.powf(e);
        }
        let Some(var) = REAL_VARIABLES.iter().find(|v| v.vr == vr) else {
            return self.rng.uniform(-10.0, 10.0);
        };
        match var.name {
            "Fz" => self.rng.uniform(-1000.0, 12000.0),
            "alpha" => self.rng.uniform(-0.5, 0.5),
            "kappa" => self.rng.uniform(-1.2, 1.2),
            "gamma" => self.rng.uniform(-0.3, 0.3),
            "vx" => self.rng.uniform(-160.0, 160.0),
            "p" => self.rng.uniform(0.0, 500_000.0),
            "T_tread" => self.rng.uniform(150.0, 600.0),
            "Fz_max" => self.rng.uniform(0.0, 20000.0),
            "gamma_max" => self.rng.uniform(-0.1, 1.7),
            _ => {
                // A parameter near its start value (the paper's table), sometimes far off.
                let start = pacejka_start(var.name);
                start * self.rng.uniform(0.5, 1.5) + self.rng.uniform(-0.1, 0.1)
            }
        }
    }

    /// Some value references of `pool`, each with chance `unknown` one of `unknowns`.
    pub(crate) fn pick_vrs(&mut self, pool: &[u32], unknown: f64, unknowns: &[u32]) -> Vec<u32> {
        let n = self.rng.pick(&[0, 1, 1, 2, 3, 4, 7]);
        (0..n)
            .map(|_| {
                if self.rng.chance(unknown) {
                    self.rng.pick(unknowns)
                } else {
                    self.rng.pick(pool)
                }
            })
            .collect()
    }

    fn some_vrs(&mut self, pool: &[u32]) -> Vec<u32> {
        self.pick_vrs(pool, 0.05, &[u32::MAX, 99, 18, 399, 1000, 12345])
    }

    /// A hostile value with chance `p`, else one in `lo..hi`.
    pub(crate) fn hostile_or(&mut self, p: f64, lo: f64, hi: f64) -> f64 {
        if self.rng.chance(p) {
            self.rng.pick(HOSTILE)
        } else {
            self.rng.uniform(lo, hi)
        }
    }

    /// `n` values of [`Generator::hostile_or`].
    pub(crate) fn hostile_values(&mut self, n: usize, p: f64, lo: f64, hi: f64) -> Vec<f64> {
        (0..n).map(|_| self.hostile_or(p, lo, hi)).collect()
    }

    /// Which of the four arrays of a derivative call is NULL (0: none).
    pub(crate) fn null_of_four(&mut self) -> u8 {
        if self.rng.chance(0.05) {
            1 + self.rng.below(4) as u8
        } else {
            0
        }
    }

    /// `loggingOn`, the categories and the array of a SetDebugLogging of either standard.
    pub(crate) fn debug_logging(&mut self) -> (bool, Vec<Option<&'static str>>, Arr) {
        let n = self.rng.below(4);
        let categories = (0..n)
            .map(|_| {
                self.rng.pick(&[
                    Some("logStatusError"),
                    Some("logStatusWarning"),
                    Some("logEvents"),
                    Some("logCalls"),
                    Some("nonsense"),
                    Some(""),
                    None,
                ])
            })
            .collect();
        (self.rng.chance(0.5), categories, self.arr())
    }

    /// An instantiation argument: 0 (right), or when `hostile` with chance 0.2 one of the
    /// `n - 1` wrong ones.
    pub(crate) fn bad(&mut self, hostile: bool, n: u8) -> u8 {
        if hostile && self.rng.chance(0.2) {
            1 + self.rng.below(n as usize - 1) as u8
        } else {
            0
        }
    }

    /// Tolerance, start and stop time of fmi2SetupExperiment and fmi3EnterInitializationMode.
    pub(crate) fn experiment(&mut self, hostile: bool) -> (Option<f64>, f64, Option<f64>) {
        let value = |g: &mut Generator| {
            if hostile && g.rng.chance(0.3) {
                g.rng.pick(HOSTILE)
            } else {
                g.rng.uniform(0.0, 10.0)
            }
        };
        let start = value(self);
        let stop = if self.rng.chance(0.3) {
            Some(start + value(self) * 10.0)
        } else {
            None
        };
        let tolerance = self.rng.chance(0.5).then(|| value(self));
        (tolerance, start, stop)
    }

    pub(crate) fn arr(&mut self) -> Arr {
        match self.rng.below(20) {
            0 => Arr::Null1,
            1 => Arr::Null2,
            _ => Arr::Ok,
        }
    }

    pub(crate) fn state_ref(&mut self) -> StateRef {
        match self.rng.below(12) {
            0 => StateRef::Garbage,
            1 | 2 => StateRef::Stale(self.rng.below(STATE_SLOTS)),
            _ => StateRef::Slot(self.rng.below(STATE_SLOTS)),
        }
    }

    pub(crate) fn time(&mut self) -> Time {
        if self.rng.chance(0.8) {
            Time::Current
        } else {
            Time::Value(self.hostile_or(0.5, -1.0, 10.0))
        }
    }

    pub(crate) fn step_size(&mut self) -> f64 {
        if self.rng.chance(0.85) {
            self.rng.pick(&[1e-3, 0.01, 0.1, 1.0, 1e-9])
        } else {
            self.rng.pick(HOSTILE)
        }
    }

    pub(crate) fn corrupt(&mut self) -> Corrupt {
        let permille = |r: &mut Rng| r.below(1001) as u16;
        match self.rng.below(10) {
            0..=2 => Corrupt::None,
            3 => Corrupt::Truncate(permille(&mut self.rng)),
            4 => Corrupt::Flip {
                at: permille(&mut self.rng),
                mask: 1 << self.rng.below(8),
            },
            5 | 6 => Corrupt::Number {
                nth: self.rng.below(80) as u16,
                with: self.rng.pick(&[
                    "1e999",
                    "-1e999",
                    "NaN",
                    "5e-324",
                    "1.7e308",
                    "-1.7e308",
                    "-0",
                    "\"x\"",
                    "null",
                    "1e400",
                    "-1",
                    "99999999999999999999",
                    "0.0",
                    "-5",
                ]),
            },
            7 => Corrupt::Word {
                nth: self.rng.below(40) as u16,
                with: self.rng.pick(&[
                    "\"Error\"",
                    "\"StepComplete\"",
                    "\"ContinuousTimeMode\"",
                    "\"EventMode\"",
                    "\"Terminated\"",
                    "\"Iso\"",
                    "null",
                    "\"\"",
                ]),
            },
            8 => Corrupt::Append(self.rng.pick(&["}", " ", "\0", "{\"x\":1}"])),
            _ => Corrupt::Empty,
        }
    }

    pub(crate) fn string_value(&mut self) -> Str {
        match self.rng.below(20) {
            0 => Str::Null,
            1 => Str::NotUtf8,
            2 => Str::Text(String::new()),
            3 => Str::Text(
                self.rng
                    .pick(&[
                        "/nonexistent/%s%n.json",
                        "/dev/zero",
                        "/",
                        "file:///nonexistent",
                        "file://host/x.json",
                        "../../../../etc/passwd",
                        "\u{1F600}.json",
                    ])
                    .to_string(),
            ),
            _ if self.rng.chance(0.6) => Str::File(self.rng.below(self.good_files)),
            _ => Str::File(self.rng.below(self.files)),
        }
    }

    /// Any call of the sequence's standards, any arguments.
    fn random(&mut self) -> Op {
        let fmi3 = match self.mode {
            Mode::Fmi2 => false,
            Mode::Fmi3 => !self.rng.chance(0.03),
            Mode::Mixed => self.rng.chance(0.5),
        };
        if fmi3 {
            let op = Op::Fmi3(self.random3());
            self.track(&op);
            op
        } else {
            self.random2()
        }
    }

    /// Any FMI 2.0 call, any arguments.
    fn random2(&mut self) -> Op {
        let inst = self.rng.below(INSTANCES);
        let op = match self.rng.below(44) {
            0 => Op::GetTypesPlatform,
            1 => Op::GetVersion,
            2 => self.instantiate(inst, true),
            3 => Op::FreeInstance { inst },
            4 => {
                let (on, categories, arr) = self.debug_logging();
                Op::SetDebugLogging {
                    inst,
                    on,
                    categories,
                    arr,
                }
            }
            5 => self.setup(inst, true),
            6 => Op::EnterInitializationMode { inst },
            7 => Op::ExitInitializationMode { inst },
            8 => Op::Terminate { inst },
            9 => Op::Reset { inst },
            10 => {
                let all = self.all_real.clone();
                Op::GetReal {
                    inst,
                    vrs: self.some_vrs(&all),
                    arr: self.arr(),
                }
            }
            11 => Op::GetInteger {
                inst,
                vrs: self.some_vrs(&[0, 1]),
                arr: self.arr(),
            },
            12 => Op::GetBoolean {
                inst,
                vrs: self.some_vrs(&[0]),
                arr: self.arr(),
            },
            13 => Op::GetString {
                inst,
                vrs: self.some_vrs(&[0]),
                arr: self.arr(),
            },
            14 => {
                let all = self.all_real.clone();
                self.set_real(inst, &all)
            }
            15 => {
                let vrs = self.some_vrs(&[0, 7]);
                let values = vrs.iter().map(|_| self.rng.next() as i32).collect();
                Op::SetInteger {
                    inst,
                    vrs,
                    values,
                    arr: self.arr(),
                }
            }
            16 => {
                let vrs = self.some_vrs(&[0]);
                let values = vrs
                    .iter()
                    .map(|_| self.rng.pick(&[0, 1, 2, -1, i32::MIN]))
                    .collect();
                Op::SetBoolean {
                    inst,
                    vrs,
                    values,
                    arr: self.arr(),
                }
            }
            17 => {
                let vrs = self.some_vrs(&[0]);
                let values = vrs.iter().map(|_| self.string_value()).collect();
                Op::SetString {
                    inst,
                    vrs,
                    values,
                    arr: self.arr(),
                }
            }
            k @ 18..=23 => random_state_op!(self, inst, k - 18, Op:
                GetFMUstate, SetFMUstate, FreeFMUstate,
                SerializedFMUstateSize, SerializeFMUstate, DeSerializeFMUstate),
            24 => self.directional(inst),
            25 => Op::SetRealInputDerivatives { inst },
            26 => Op::GetRealOutputDerivatives { inst },
            27 => Op::DoStep {
                inst,
                t: self.time(),
                h: self.step_size(),
            },
            28 => Op::CancelStep { inst },
            29..=31 => Op::GetStatus {
                inst,
                which: self.rng.below(5) as u8,
                kind: self.rng.pick(&[0, 1, 2, 3, 4, -1, 99]),
                null: self.rng.chance(0.1),
            },
            32 => Op::EnterEventMode { inst },
            33 => Op::NewDiscreteStates {
                inst,
                null: self.rng.chance(0.1),
            },
            34 => Op::EnterContinuousTimeMode { inst },
            35 => Op::CompletedIntegratorStep {
                inst,
                null: self.rng.chance(0.1),
            },
            36 => Op::SetTime {
                inst,
                t: self.time(),
            },
            37 => self.set_states(inst),
            38 => Op::GetContinuousStates {
                inst,
                n: self.count(),
                null: self.rng.chance(0.05),
            },
            39 => Op::GetDerivatives {
                inst,
                n: self.count(),
                null: self.rng.chance(0.05),
            },
            40 => Op::GetNominalsOfContinuousStates {
                inst,
                n: self.count(),
                null: self.rng.chance(0.05),
            },
            41 => Op::GetEventIndicators {
                inst,
                n: self.rng.pick(&[0, 0, 1, 3]),
                null: self.rng.chance(0.2),
            },
            _ => {
                let locals = self.locals.clone();
                Op::GetReal {
                    inst,
                    vrs: self.some_vrs(&locals),
                    arr: Arr::Ok,
                }
            }
        };
        self.track(&op);
        op
    }

    pub(crate) fn count(&mut self) -> usize {
        self.rng.pick(&[3, 3, 3, 3, 0, 2, 4])
    }

    fn instantiate(&mut self, inst: usize, hostile: bool) -> Op {
        let fmu_type = if hostile && self.rng.chance(0.05) {
            self.rng.pick(&[2, -1, 99])
        } else {
            self.rng.below(2) as i32
        };
        Op::Instantiate {
            inst,
            fmu_type,
            name: self.bad(hostile, 3),
            guid: self.bad(hostile, 3),
            resources: self.bad(hostile, 4),
            callbacks: self.bad(hostile, 4),
            logging: self.rng.chance(0.5),
        }
    }

    fn setup(&mut self, inst: usize, hostile: bool) -> Op {
        let (tolerance, start, stop) = self.experiment(hostile);
        Op::SetupExperiment {
            inst,
            tolerance,
            start,
            stop,
        }
    }

    fn set_real(&mut self, inst: usize, pool: &[u32]) -> Op {
        let vrs = self.some_vrs(pool);
        let values = vrs.iter().map(|vr| self.real_value(*vr)).collect();
        Op::SetReal {
            inst,
            vrs,
            values,
            arr: self.arr(),
        }
    }

    /// fmi2GetReal of some Real variables.
    fn get_real(&mut self, inst: usize) -> Op {
        let all = self.all_real.clone();
        Op::GetReal {
            inst,
            vrs: self.some_vrs(&all),
            arr: Arr::Ok,
        }
    }

    /// fmi2SetReal of the inputs and vx, and of p and T_tread with `conditions`.
    fn set_inputs(&mut self, inst: usize, conditions: bool) -> Op {
        let mut pool = self.inputs.clone();
        pool.push(self.speed);
        if conditions {
            pool.extend(&self.conditions);
        }
        self.set_real(inst, &pool)
    }

    fn set_states(&mut self, inst: usize) -> Op {
        let n = self.count();
        let x = self.hostile_values(n, 0.2, -1.5, 1.5);
        Op::SetContinuousStates {
            inst,
            x,
            null: self.rng.chance(0.05),
        }
    }

    fn directional(&mut self, inst: usize) -> Op {
        let mut unknown_pool = self.outputs.clone();
        unknown_pool.extend(self.locals.iter().filter(|vr| {
            REAL_VARIABLES
                .iter()
                .any(|v| v.vr == **vr && v.name.starts_with("der("))
        }));
        let mut known_pool = self.inputs.clone();
        known_pool.push(self.speed);
        known_pool.extend(&self.conditions);
        known_pool.extend(self.locals.iter().filter(|vr| {
            REAL_VARIABLES
                .iter()
                .any(|v| v.vr == **vr && v.name.starts_with("lag_"))
        }));
        if self.rng.chance(0.1) {
            known_pool.extend(&self.outputs);
            unknown_pool.extend(&self.inputs);
        }
        let unknown = self.some_vrs(&unknown_pool);
        let known = self.some_vrs(&known_pool);
        let dv = self.hostile_values(known.len(), 0.15, -2.0, 2.0);
        let null = self.null_of_four();
        Op::GetDirectionalDerivative {
            inst,
            unknown,
            known,
            dv,
            null,
        }
    }

    /// A call that fits the state the picked instance is expected to be in, of the standard
    /// that made it (a free slot gets an instance of the sequence's standard, or of either).
    fn guided(&mut self) -> Op {
        let inst = self.rng.below(INSTANCES);
        let r = self.rng.below(100);
        let fmi3 = match (self.mode, self.expect[inst]) {
            (Mode::Fmi2, _) => false,
            (Mode::Fmi3, Expect::Free) => true,
            (Mode::Mixed, Expect::Free) => self.rng.chance(0.5),
            _ => self.fmi3[inst],
        };
        if fmi3 {
            let op = Op::Fmi3(self.guided3(inst, r));
            self.track(&op);
            return op;
        }
        let op = match self.expect[inst] {
            Expect::Free => self.instantiate(inst, false),
            Expect::Instantiated { .. } => match r {
                0..=24 => Op::SetString {
                    inst,
                    vrs: vec![0],
                    values: vec![self.string_value()],
                    arr: Arr::Ok,
                },
                25..=44 => {
                    let pool = self.parameters.clone();
                    self.set_real(inst, &pool)
                }
                45..=49 => Op::SetBoolean {
                    inst,
                    vrs: vec![0],
                    values: vec![self.rng.below(2) as i32],
                    arr: Arr::Ok,
                },
                50..=59 => self.set_inputs(inst, false),
                60..=69 => self.setup(inst, false),
                70..=74 => self.state_op(inst),
                _ => Op::EnterInitializationMode { inst },
            },
            Expect::Init { me } => match r {
                0..=19 => self.set_inputs(inst, true),
                20..=29 => self.get_real(inst),
                30..=39 => self.directional(inst),
                40..=44 if me => Op::GetContinuousStates {
                    inst,
                    n: 3,
                    null: false,
                },
                45..=49 => self.state_op(inst),
                _ => Op::ExitInitializationMode { inst },
            },
            Expect::Step => match r {
                0..=34 => Op::DoStep {
                    inst,
                    t: Time::Current,
                    h: self.step_size(),
                },
                35..=49 => self.set_inputs(inst, true),
                50..=59 => self.get_real(inst),
                60..=67 => self.directional(inst),
                68..=84 => self.state_op(inst),
                85..=89 => Op::GetStatus {
                    inst,
                    which: 1,
                    kind: 2,
                    null: false,
                },
                90..=94 => Op::Terminate { inst },
                95..=97 => Op::Reset { inst },
                _ => Op::FreeInstance { inst },
            },
            Expect::Event => match r {
                0..=39 => Op::EnterContinuousTimeMode { inst },
                40..=49 => Op::NewDiscreteStates { inst, null: false },
                50..=64 => self.set_inputs(inst, false),
                65..=79 => self.state_op(inst),
                80..=89 => self.get_real(inst),
                90..=95 => Op::Terminate { inst },
                _ => Op::Reset { inst },
            },
            Expect::Continuous => match r {
                0..=9 => Op::SetTime {
                    inst,
                    t: Time::Value(self.rng.uniform(0.0, 10.0)),
                },
                10..=24 => self.set_states(inst),
                25..=39 => Op::GetDerivatives {
                    inst,
                    n: 3,
                    null: false,
                },
                40..=44 => Op::GetContinuousStates {
                    inst,
                    n: 3,
                    null: false,
                },
                45..=54 => self.directional(inst),
                55..=59 => Op::CompletedIntegratorStep { inst, null: false },
                60..=72 => self.set_inputs(inst, true),
                73..=84 => self.state_op(inst),
                85..=89 => self.get_real(inst),
                90..=93 => Op::EnterEventMode { inst },
                94..=97 => Op::GetNominalsOfContinuousStates {
                    inst,
                    n: 3,
                    null: false,
                },
                _ => Op::Terminate { inst },
            },
            Expect::Terminated { .. } => match r {
                0..=29 => self.get_real(inst),
                30..=49 => self.directional(inst),
                50..=64 => self.state_op(inst),
                65..=84 => Op::Reset { inst },
                _ => Op::FreeInstance { inst },
            },
        };
        self.track(&op);
        op
    }

    /// Saving, restoring, serializing and reading back FMU states.
    fn state_op(&mut self, inst: usize) -> Op {
        let slot = self.rng.below(STATE_SLOTS);
        match self.rng.below(6) {
            0 | 1 => Op::GetFMUstate {
                inst,
                slot,
                null_slot: false,
            },
            2 => Op::SetFMUstate {
                inst,
                state: StateRef::Slot(slot),
            },
            3 => Op::SerializeFMUstate {
                inst,
                state: StateRef::Slot(slot),
                buffer: slot,
                size_delta: 0,
                null: false,
            },
            4 => Op::DeSerializeFMUstate {
                inst,
                buffer: self.rng.below(STATE_SLOTS),
                corrupt: self.corrupt(),
                slot,
                arr: Arr::Ok,
            },
            _ => Op::FreeFMUstate {
                inst,
                state: StateRef::Slot(slot),
                null_slot: false,
            },
        }
    }

    /// Where `op` takes its instance, if it succeeds. A call of the other standard than the
    /// one that made the instance is refused and changes nothing; an instantiation replaces
    /// the instance (the host frees the one in the slot first).
    fn track(&mut self, op: &Op) {
        if let Op::Fmi3(op3) = op {
            self.track3(op3);
            return;
        }
        if self.mode != Mode::Fmi2 {
            match *op {
                Op::Instantiate {
                    inst,
                    fmu_type,
                    name,
                    guid,
                    callbacks,
                    ..
                } => {
                    let made = name == 0 && guid == 0 && callbacks == 0;
                    let me = (made && (0..2).contains(&fmu_type)).then_some(fmu_type == 0);
                    self.instantiated(inst, me, false);
                    return;
                }
                Op::FreeInstance { inst } => {
                    self.freed(inst);
                    return;
                }
                _ => {}
            }
            if op.inst().is_some_and(|i| self.fmi3[i]) {
                return;
            }
        }
        let e = &mut self.expect;
        match *op {
            Op::Instantiate {
                inst,
                fmu_type,
                name: 0,
                guid: 0,
                callbacks: 0,
                ..
            } if e[inst] == Expect::Free && (0..2).contains(&fmu_type) => {
                e[inst] = Expect::Instantiated { me: fmu_type == 0 }
            }
            Op::FreeInstance { inst } => e[inst] = Expect::Free,
            _ => {}
        }
        if let Some((inst, t)) = op.transition() {
            e[inst] = e[inst].after(t);
        }
    }

    /// An instantiation of either standard in slot `inst`: made (Model Exchange or not) or
    /// not; the states of the instance it replaced go with that.
    pub(crate) fn instantiated(&mut self, inst: usize, me: Option<bool>, fmi3: bool) {
        self.expect[inst] = me.map_or(Expect::Free, |me| Expect::Instantiated { me });
        self.fmi3[inst] = fmi3;
        self.forget_states(inst);
    }

    /// A FreeInstance of either standard in slot `inst`.
    pub(crate) fn freed(&mut self, inst: usize) {
        self.expect[inst] = Expect::Free;
        self.forget_states(inst);
    }

    /// The states of instance `inst` go with it.
    fn forget_states(&mut self, inst: usize) {
        for held in &mut self.held {
            if *held == Some(inst) {
                *held = None;
            }
        }
    }
}

/// The start value of a parameter (the paper's table, from the model description).
fn pacejka_start(name: &str) -> f64 {
    pacejka87_tire::variables::REAL_VARIABLES
        .iter()
        .find(|v| v.name == name)
        .map(|v| v.start_value())
        .unwrap_or(1.0)
}
