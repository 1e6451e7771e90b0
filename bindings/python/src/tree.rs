//! `Tree`: the succinct tree (`succinct::PaperTree`,
//! `succinct::LevelOrderTree`) of one micromap.

use crate::arrays::{dtype_name, has_dtype, readonly, type_name};
use crate::fallible::try_vec;
use crate::options::{self, value_error};
use micromap_index::micromap::State;
use micromap_index::succinct::{LevelOrderTree, PaperTree, TreeError};
use micromap_index::Level;
use numpy::{PyArray1, PyArrayMethods, PyUntypedArray, PyUntypedArrayMethods};
use pyo3::exceptions::{PyMemoryError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

enum Layout {
    Paper(PaperTree),
    LevelOrder(LevelOrderTree),
}

/// One micromap as a succinct tree: the paper's depth-first layout
/// (`"paper"`) or the level order with a rank directory (`"level-order"`).
/// States are ints: 0 transparent, 1 opaque, 2 unknown-transparent,
/// 3 unknown-opaque.
#[pyclass(frozen, module = "micromap_index")]
pub(crate) struct Tree {
    tree: Layout,
}

macro_rules! each {
    ($self:expr, $t:ident => $body:expr) => {
        match &$self.tree {
            Layout::Paper($t) => $body,
            Layout::LevelOrder($t) => $body,
        }
    };
}

/// `states` as the library's states: a uint8 numpy array (any shape, read
/// in C order) or bytes, each 0..=3, into one fallibly reserved buffer.
fn states(obj: &Bound<'_, PyAny>) -> PyResult<Vec<State>> {
    let state = |i: usize, b: u8| {
        State::from_bits(b)
            .ok_or_else(|| value_error(format!("states[{i}] = {b}: expected a state 0..=3")))
    };
    if let Ok(b) = obj.downcast::<PyBytes>() {
        let bytes = b.as_bytes();
        let mut out = try_vec(bytes.len(), "states")?;
        for (i, &b) in bytes.iter().enumerate() {
            out.push(state(i, b)?);
        }
        return Ok(out);
    }
    let Ok(array) = obj.downcast::<PyUntypedArray>() else {
        return Err(PyTypeError::new_err(format!(
            "states must be a uint8 numpy array or bytes, not {}",
            type_name(obj)
        )));
    };
    if !has_dtype::<u8>(array) {
        return Err(PyTypeError::new_err(format!(
            "states must have dtype uint8, not {}",
            dtype_name(array)
        )));
    }
    let read = readonly::<u8>(array, "states")?;
    let view = read.as_array();
    let mut out = try_vec(view.len(), "states")?;
    for (i, &b) in view.iter().enumerate() {
        out.push(state(i, b)?);
    }
    Ok(out)
}

/// A micro-triangle index from a Python int, or a `ValueError`.
fn index_value(obj: &Bound<'_, PyAny>) -> PyResult<u64> {
    match obj.extract::<i128>() {
        Ok(i) => {
            u64::try_from(i).map_err(|_| value_error(format!("index {i} is negative or too large")))
        }
        Err(_) => Err(PyTypeError::new_err(format!(
            "index must be an int or an integer numpy array, not {}",
            type_name(obj)
        ))),
    }
}

impl Tree {
    fn get(&self, index: u64) -> PyResult<u8> {
        each!(self, t => t.get(index))
            .map(State::bits)
            .ok_or_else(|| {
                value_error(format!(
                    "micro-triangle {index} is past the tree's last ({} at level {})",
                    // Levels read from bytes may reach 32, where 4^level is 2^64.
                    1u128
                        .checked_shl(2 * self.level())
                        .map_or(u128::MAX, |n| n - 1),
                    self.level()
                ))
            })
    }

    fn level(&self) -> u32 {
        each!(self, t => t.level().get())
    }
}

#[pymethods]
impl Tree {
    /// Encodes the flat micromap `states` (`4 ** level` of them, in curve
    /// order) at `level` (0..=16) in `format` (2 or 4; a 2-state tree
    /// refuses unknown states) and `layout` (`"paper"` or
    /// `"level-order"`).
    #[staticmethod]
    #[pyo3(signature = (states, level, format = 4, layout = "paper"))]
    fn encode(states: &Bound<'_, PyAny>, level: i64, format: i64, layout: &str) -> PyResult<Tree> {
        let level = u32::try_from(level)
            .ok()
            .filter(|&l| l <= 16)
            .and_then(|l| Level::new(l).ok())
            .ok_or_else(|| value_error(format!("level {level}: expected 0..=16")))?;
        let format = options::format(format)?;
        let states = self::states(states)?;
        let tree = match layout {
            "paper" => PaperTree::encode(level, format, &states).map(Layout::Paper),
            "level-order" => LevelOrderTree::encode(level, format, &states).map(Layout::LevelOrder),
            other => {
                return Err(value_error(format!(
                    "layout {other:?}: expected \"paper\" or \"level-order\""
                )))
            }
        }
        .map_err(|e| match e {
            TreeError::AllocationFailed { .. } => PyMemoryError::new_err(e.to_string()),
            e => value_error(e),
        })?;
        Ok(Tree { tree })
    }

    /// Reads the bytes `to_bytes` writes (either layout); anything else is
    /// a `ValueError`.
    #[staticmethod]
    fn from_bytes(bytes: &[u8]) -> PyResult<Tree> {
        // Byte 5 names the layout (the format table in `succinct`); each
        // reader checks everything, that byte included.
        let tree = if bytes.get(5) == Some(&0) {
            PaperTree::from_bytes(bytes).map(Layout::Paper)
        } else {
            LevelOrderTree::from_bytes(bytes).map(Layout::LevelOrder)
        };
        Ok(Tree {
            tree: tree.map_err(value_error)?,
        })
    }

    /// The tree's bytes (`Tree.from_bytes` reads them back).
    fn to_bytes<'py>(&self, py: Python<'py>) -> Bound<'py, PyBytes> {
        PyBytes::new(py, &each!(self, t => t.to_bytes()))
    }

    /// The state of micro-triangle `index`: an int gives an int, an
    /// integer array a uint8 array of its shape. An index `>= 4 ** level`
    /// (or negative) is a `ValueError`.
    fn lookup(&self, py: Python<'_>, index: &Bound<'_, PyAny>) -> PyResult<PyObject> {
        let Ok(array) = index.downcast::<PyUntypedArray>() else {
            return Ok(self
                .get(index_value(index)?)?
                .into_pyobject(py)?
                .into_any()
                .unbind());
        };
        // Read in place (the GIL is held): a broadcast view is never
        // copied; the result, sized by the input, is reserved first.
        let shape = array.shape().to_vec();
        let mut states = try_vec::<u8>(array.len(), "lookup's result")?;
        if has_dtype::<u64>(array) {
            let read = readonly::<u64>(array, "index")?;
            for &i in read.as_array() {
                states.push(self.get(i)?);
            }
        } else if has_dtype::<i64>(array) {
            let read = readonly::<i64>(array, "index")?;
            for &i in read.as_array() {
                let i =
                    u64::try_from(i).map_err(|_| value_error(format!("index {i} is negative")))?;
                states.push(self.get(i)?);
            }
        } else {
            return Err(PyTypeError::new_err(format!(
                "index must have dtype int64 or uint64, not {}",
                dtype_name(array)
            )));
        }
        Ok(PyArray1::from_vec(py, states)
            .reshape(shape)?
            .into_any()
            .unbind())
    }

    /// The state a ray hit at barycentrics `(u, v)` reads (each rounded
    /// to float32): the Vulkan reference index, then the lookup.
    fn state_at(&self, u: f32, v: f32) -> PyResult<u8> {
        each!(self, t => t.get_f32(u, v))
            .map(State::bits)
            .ok_or_else(|| PyValueError::new_err("no state at this point"))
    }

    /// Every state in curve order, as a uint8 array.
    /// A level-16 tree decodes to 4 GiB: the states are written run by
    /// run into one buffer reserved fallibly (`MemoryError` where it
    /// cannot be had), and handed to numpy without a copy.
    fn decode<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<u8>>> {
        let count = 1u64 << (2 * each!(self, t => t.level()).get());
        let len = usize::try_from(count)
            .map_err(|_| crate::fallible::memory_error("the states", usize::MAX, 1))?;
        let mut states: Vec<u8> = try_vec(len, "the states")?;
        states.resize(len, 0);
        each!(self, t => t.for_each_run(|first, n, state| {
            // The runs tile 0..4^level = 0..len.
            states[first as usize..(first + n) as usize].fill(state.bits());
        }));
        Ok(PyArray1::from_vec(py, states))
    }

    /// The subdivision level.
    #[getter(level)]
    fn level_getter(&self) -> u32 {
        self.level()
    }

    /// 2 or 4.
    #[getter]
    fn format(&self) -> u32 {
        each!(self, t => t.format()).states()
    }

    /// `"paper"` or `"level-order"`.
    #[getter]
    fn layout(&self) -> &'static str {
        match self.tree {
            Layout::Paper(_) => "paper",
            Layout::LevelOrder(_) => "level-order",
        }
    }

    /// The tree's size in bits (tree bits, leaf states and, for the level
    /// order, its rank directory).
    #[getter]
    fn total_bits(&self) -> u64 {
        each!(self, t => t.total_bits())
    }

    /// Leaf states stored.
    #[getter]
    fn leaf_count(&self) -> u64 {
        each!(self, t => t.leaf_count())
    }

    fn __repr__(&self) -> String {
        format!(
            "Tree(layout={:?}, level={}, format={}, total_bits={})",
            self.layout(),
            self.level(),
            self.format(),
            self.total_bits()
        )
    }
}
