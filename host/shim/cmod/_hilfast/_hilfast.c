// _hilfast: the shim's per-edge hot path in C, for the harness's own MicroPython build.
//
// host/shim/_hil.py uses it when it can import it (and HIL_PURE is not set); a user's own
// interpreter runs the pure-Python path, which does exactly the same thing: the tests run
// both and compare the traces byte for byte (host/tests/test_hilfast.py). One function:
//
// apply_state(p, cur, base, t_end, n, handles, pin_type, pending, watch, ctx, g[, edges])
//   applies a STATE's changes from offset cur[0] (change cur[1] of n) as _hil._sync's loop
//   does (with edges, the EDGES that came with it: its encoder segments' edges, expanded
//   here, merged in time order, an instant's edges first, as _hil._apply_state does with an EDGES): at each new instant first the handlers due at the one before (_handlers_wrote and
//   dispatch, here in C; ctx: (_hil's globals, _Link, CallbackFailed)), then _now = t (in
//   the module globals g, None in real time), then each change:
//   a machine.Pin (exactly pin_type, no counters) in C as Pin._hil_apply does, anything
//   else through its own _hil_apply. It stops at the first change past t_end (held by the
//   caller), or when _handlers_wrote says to stop. cur gets [offset, index, watched hit];
//   returns handlers_wrote's stop code (0: every change up to t_end applied).
//
// merge_edges(edges, base, changes): a STATE's changes with its EDGES' edges merged in, for
//   _hil._apply_state (where apply_state cannot run: a callback, IRQs off, a C call).
// pin_setup(value_py, out_mode, g), pin_value: machine.Pin.value in C (below).
//
// With the counting interpreter (host/core/micropython/hilcount.patch, py/hilcount.h), the
// board's own time (docs/mcu-time.md):
// arm(fn): fn() at the firmware's next bytecode branch (below: the scheduled callbacks left
//   queued run there, one a branch, as on a board).
// exempt(folder): the functions of modules whose source file starts with folder (the
//   shim's: a board has it in C) are not counted, nor what they allocate or call (up to
//   four folders: the shim's, as it was compiled before and after the sandbox).
// cost(weights, heap): set the cost model (heap: the board's heap, in this build's bytes,
//   the firmware's collections are scheduled by and charged in), a bytes of 264 little-endian uint32 in picoseconds:
//   one per opcode byte, then a call into C, an allocation, an allocated byte, a collection,
//   a byte in use at a collection, a byte of heap at a collection, a wide int result, a bit of a big-int result.
// owed_us(): the whole µs of MCU time the main program's work since the last call costs
//   (the rest carried to the next); irq_begin(), irq_end(now): a batch of callbacks runs
//   (their work keeps the CPU busy from now); busy_us(): until when callbacks keep it busy;
// owing_us(): what owed_us() would say, taking nothing;
// branches(fn, every): fn() at every every-th branch of the firmware's own code (a loop that
//   calls nothing of the board's: the shim moves virtual time there, _hil._branches);
// counts(): the raw counters (a dict, for calibration);
// stack(all=False): the running bytecode functions, outermost first, as
//   [(file, function, line)]; without all, only the firmware's (not the exempt modules').
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <stddef.h>
#include <string.h>
#include <unistd.h>

#include "py/bc.h"
#include "py/gc.h"
#include "py/mpstate.h"
#include "py/hilcount.h"
#include "py/obj.h"
#include "py/objfun.h"
#include "py/objlist.h"
#include "py/objtuple.h"
#include "py/objtype.h"
#include "py/runtime.h"
#include "py/smallint.h"

#define CHANGE_LEN 15  // "<IHBiI": dt_us, handle, kind, value, extra
#define CH_BYTES 2     // _hilframe.CH_BYTES: value is a byte count, the bytes follow
#define IRQ_RISING 1   // _hilframe.IRQ_RISING / IRQ_FALLING (the ESP32 port's codes)
#define IRQ_FALLING 2

static uint32_t get_u32(const uint8_t *b) {
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static bool is_hard(mp_obj_t arg);
static size_t queue_depth = 8;  // _Link.depth (MICROPY_SCHEDULER_DEPTH), read by apply_state
static mp_obj_t shim_globals;  // _hil's (apply_state's ctx[0]: it holds them), for _lost

// An attribute an instance of a class of Python's holds itself (in its members: where the
// attribute's load looks first, py/objtype.c mp_obj_instance_load_attr), else the generic load.
static mp_obj_t inst_get(mp_obj_t obj, qstr name) {
    if (mp_obj_is_obj(obj) && mp_obj_is_instance_type(mp_obj_get_type(obj))) {
        mp_obj_instance_t *o = MP_OBJ_TO_PTR(obj);
        mp_map_elem_t *e = mp_map_lookup(&o->members, MP_OBJ_NEW_QSTR(name), MP_MAP_LOOKUP);
        if (e != NULL) {
            return e->value;
        }
    }
    return mp_load_attr(obj, name);
}

// A machine.Pin's own attribute set (the class has no property or __setattr__ of that name:
// the store's checks for them find nothing), else the generic store.
static void pin_set(mp_obj_t pin, qstr name, mp_obj_t value) {
    mp_obj_instance_t *o = MP_OBJ_TO_PTR(pin);
    mp_map_elem_t *e = mp_map_lookup(&o->members, MP_OBJ_NEW_QSTR(name), MP_MAP_LOOKUP);
    if (e != NULL) {
        e->value = value;
    } else {
        mp_store_attr(pin, name, value);
    }
}

// mp_sched_full's negation (_hil.room): the queue holds fewer than its depth soft callbacks.
static bool room(mp_obj_t pending) {
    mp_obj_list_t *list = MP_OBJ_TO_PTR(pending);
    if (list->len < queue_depth) {
        return true;
    }
    size_t n = 0;
    for (size_t i = 0; i < list->len; i++) {
        mp_obj_t *cb;
        mp_obj_get_array_fixed_n(list->items[i], 2, &cb);
        n += !is_hard(cb[1]);
    }
    return n < queue_depth;
}

// Pin._hil_apply, for a Pin with no counters; false when it must go through Python.
static bool pin_apply(mp_obj_t pin, mp_obj_t value, mp_obj_t pending) {
    if (inst_get(pin, MP_QSTR__counters) != mp_const_none) {
        return false;
    }
    if (mp_obj_equal(inst_get(pin, MP_QSTR__level), value)) {
        return true;
    }
    pin_set(pin, MP_QSTR__level, value);
    mp_obj_t handler = inst_get(pin, MP_QSTR__handler);
    if (handler != mp_const_none) {
        mp_int_t edge = mp_obj_is_true(value) ? IRQ_RISING : IRQ_FALLING;
        if (mp_obj_get_int(inst_get(pin, MP_QSTR__trigger)) & edge) {
            pin_set(pin, MP_QSTR__flags, MP_OBJ_NEW_SMALL_INT(edge));
            if (room(pending) || is_hard(pin)) {
                mp_obj_t item[2] = {handler, pin};
                mp_obj_list_append(pending, mp_obj_new_tuple(2, item));
            } else {  // (a full queue: the call is lost, as _hil.schedule says)
                mp_call_function_1(mp_obj_dict_get(shim_globals, MP_OBJ_NEW_QSTR(MP_QSTR__lost)), handler);
            }
        }
    }
    return true;
}

static void apply_one(mp_obj_t obj, mp_obj_t pin_type, int kind, mp_obj_t value, mp_obj_t extra, mp_obj_t pending) {
    if (mp_obj_get_type(obj) == MP_OBJ_TO_PTR(pin_type) && pin_apply(obj, value, pending)) {
        return;
    }
    mp_obj_t dest[5];
    mp_load_method(obj, MP_QSTR__hil_apply, dest);
    dest[2] = MP_OBJ_NEW_SMALL_INT(kind);
    dest[3] = value;
    dest[4] = extra;
    mp_call_method_n_kw(3, 0, dest);
}

// MCU time (below): a batch of callbacks begins, ends at the virtual instant now_us.
static bool cost_on;  // cost() was called: the counters are charged
static uint64_t busy_ps;  // the virtual instant (ps) until which callbacks keep the CPU busy
// Nothing was counted since the last take: set after a batch of callbacks within one
// apply_state, whose own work between two batches (pins in C, the shim's _hil_apply) is
// the shim's, never counted; the next batch's irq_begin then has nothing to take.
static bool apply_clean;
static void irq_begin(void);
static void irq_end(mp_obj_t now_us);

static bool pending_any(mp_obj_t pending) {
    mp_obj_list_t *list = MP_OBJ_TO_PTR(pending);
    return list->len > 0;
}

// A queue entry's argument is a hard IRQ's when its _hard is true (_hil._is_hard).
// (An argument of the firmware's own, micropython.schedule's, may have a __getattr__ that
// raises: not hard, as getattr(arg, "_hard", False) says.)
static bool is_hard(mp_obj_t arg) {
    if (mp_obj_is_obj(arg) && mp_obj_is_instance_type(mp_obj_get_type(arg))) {  // (a pin's own _hard)
        mp_map_elem_t *e = mp_map_lookup(&((mp_obj_instance_t *)MP_OBJ_TO_PTR(arg))->members, MP_OBJ_NEW_QSTR(MP_QSTR__hard), MP_MAP_LOOKUP);
        if (e != NULL) {
            return mp_obj_is_true(e->value);
        }
    }
    mp_obj_t dest[2] = {MP_OBJ_NULL, MP_OBJ_NULL};
    nlr_buf_t nlr;
    if (nlr_push(&nlr) == 0) {
        mp_load_method_maybe(arg, MP_QSTR__hard, dest);
        bool hard = dest[0] != MP_OBJ_NULL && dest[1] == MP_OBJ_NULL && mp_obj_is_true(dest[0]);
        nlr_pop();
        return hard;
    }
    return false;
}

// An attribute of _Link held in the class's own dict, or NULL (then the generic load and
// store): a store there is what storing the attribute does for a class of Python's without
// accessors, less its checks for them (py/objtype.c, type_attr).
static mp_map_elem_t *class_slot(mp_obj_t link, qstr name) {
    const mp_obj_type_t *type = MP_OBJ_TO_PTR(link);
    if (!mp_obj_is_type(link, &mp_type_type) || !MP_OBJ_TYPE_HAS_SLOT(type, locals_dict)) {
        return NULL;
    }
    return mp_map_lookup(&MP_OBJ_TYPE_GET_SLOT(type, locals_dict)->map, MP_OBJ_NEW_QSTR(name), MP_MAP_LOOKUP);
}

static mp_obj_t class_get(mp_obj_t link, qstr name) {
    mp_map_elem_t *e = class_slot(link, name);
    return e != NULL ? e->value : mp_load_attr(link, name);
}

// _Link.callbacks += 1
static void count_callback(mp_obj_t link) {
    mp_map_elem_t *e = class_slot(link, MP_QSTR_callbacks);
    if (e != NULL && mp_obj_is_small_int(e->value) && MP_OBJ_SMALL_INT_VALUE(e->value) < MP_SMALL_INT_MAX) {
        e->value = MP_OBJ_NEW_SMALL_INT(MP_OBJ_SMALL_INT_VALUE(e->value) + 1);
        return;
    }
    mp_store_attr(link, MP_QSTR_callbacks, mp_binary_op(MP_BINARY_OP_ADD, mp_load_attr(link, MP_QSTR_callbacks), MP_OBJ_NEW_SMALL_INT(1)));
}

// _hil.dispatch(_Link.until), in a wait: the pending callbacks in order, never re-entrantly,
// unless IRQs are off; every hard IRQ's handler, the soft callbacks while the clock is not
// past the wait's end (_Link.until), as the port's wait serves its scheduler, one callback a
// pass (py/scheduler.c, mp_sched_run_pending). Those left: _hil.dispatch arms _at_branch.
// ctx: (the _hil module's globals, _Link, CallbackFailed).
static void dispatch(mp_obj_t ctx, mp_obj_t pending) {
    mp_obj_t *c = ((mp_obj_tuple_t *)MP_OBJ_TO_PTR(ctx))->items;
    mp_obj_t g = c[0], link = c[1], failed = c[2];
    mp_obj_t dispatching = MP_OBJ_NEW_QSTR(MP_QSTR__dispatching);
    if (mp_obj_is_true(mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(MP_QSTR__irq_off)))) {
        return;
    }
    if (mp_obj_is_true(mp_obj_dict_get(g, dispatching))
        || mp_obj_is_true(mp_binary_op(MP_BINARY_OP_MORE_EQUAL, mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(MP_QSTR__now)),
            class_get(link, MP_QSTR_defer_from)))) {
        // inside a callback, or from _Link.defer_from on (what is a C call on a board): the hard
        // IRQs' handlers only (_hil._run_hard, unless one runs), the soft callbacks stay queued
        if (!mp_obj_is_true(class_get(link, MP_QSTR_hard))) {
            mp_call_function_0(mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(MP_QSTR__run_hard)));
            apply_clean = false;  // (what a handler computed is taken by the next batch's irq_begin)
        }
        return;
    }
    mp_map_elem_t *until_slot = class_slot(link, MP_QSTR_until);
    mp_obj_t until_attr[2] = {MP_OBJ_NULL, MP_OBJ_NULL};
    if (until_slot == NULL) {
        mp_load_method_maybe(link, MP_QSTR_until, until_attr);
    }
    mp_obj_t wait_end = until_slot != NULL ? until_slot->value : until_attr[0];  // (MP_OBJ_NULL from a shim before it: no limit)
    mp_int_t until = wait_end != MP_OBJ_NULL ? mp_obj_get_int(wait_end) : 0;
    mp_obj_dict_store(g, dispatching, mp_const_true);
    if (!apply_clean) {
        irq_begin();
    }
    mp_obj_list_t *list = MP_OBJ_TO_PTR(pending);
    size_t i = 0;
    size_t end = list->len;  // (those a callback queues run at the wait's next pass)
    while (i < end) {
        mp_obj_t item = list->items[i];
        mp_obj_t *cb;
        mp_obj_get_array_fixed_n(item, 2, &cb);
        mp_obj_t callback = cb[0], arg = cb[1];
        if (wait_end != MP_OBJ_NULL && !is_hard(arg)
            && (mp_obj_get_int(mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(MP_QSTR__now))) > until
                || (cost_on && (mp_int_t)((busy_ps + 999999) / 1000000) > until))) {
            i++;  // (the wait is over: the rest wait for the firmware's branches)
            continue;
        }
        list->len--;  // del pending[i]
        end--;
        memmove(list->items + i, list->items + i + 1, (list->len - i) * sizeof(mp_obj_t));
        list->items[list->len] = MP_OBJ_NULL;
        count_callback(link);
        // _hil._cb_reads: a soft callback's reads counted from 0 (past SPIN_LIMIT they move
        // time: _hil._callback_read), a hard handler's held (a shim before it has none)
        mp_map_elem_t *reads = mp_map_lookup(&((mp_obj_dict_t *)MP_OBJ_TO_PTR(g))->map,
            MP_OBJ_NEW_QSTR(MP_QSTR__cb_reads), MP_MAP_LOOKUP);
        if (reads != NULL) {
            reads->value = is_hard(arg) ? mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(MP_QSTR__HELD)) : MP_OBJ_NEW_SMALL_INT(0);
        }
        nlr_buf_t nlr;
        if (nlr_push(&nlr) == 0) {
            mp_call_function_1(callback, arg);
            nlr_pop();
            if (cost_on) {  // (each one's compute from its instant or the end of the one before)
                irq_end(mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(MP_QSTR__now)));
            }
        } else {
            mp_obj_dict_store(g, dispatching, mp_const_false);
            if (cost_on) {
                irq_end(mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(MP_QSTR__now)));
            }
            mp_obj_t exc = MP_OBJ_FROM_PTR(nlr.ret_val);
            if (mp_obj_is_subclass_fast(MP_OBJ_FROM_PTR(mp_obj_get_type(exc)), MP_OBJ_FROM_PTR(&mp_type_Exception))) {
                nlr_raise(mp_call_function_2(failed, callback, exc));  // (a reset, a host stop go through)
            }
            nlr_jump(nlr.ret_val);
        }
    }
    mp_obj_dict_store(g, dispatching, mp_const_false);
    if (wait_end != MP_OBJ_NULL) {
        mp_map_elem_t *e = class_slot(link, MP_QSTR_until);  // (a callback's own wait set it)
        if (e != NULL) {
            e->value = wait_end;
        } else {
            mp_store_attr(link, MP_QSTR_until, wait_end);
        }
    }
    if (cost_on) {
        irq_end(mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(MP_QSTR__now)));
        apply_clean = true;
    }
}

static mp_obj_t global(mp_obj_t g, qstr name) {
    return mp_obj_dict_get(g, MP_OBJ_NEW_QSTR(name));
}

// _hil._handlers_wrote(t): run the handlers due at t; 1 if they wrote an output, 2 if they
// made a polled stream ready, 3 if one blocked (made exchanges), 0: carry on.
static mp_int_t handlers_wrote(mp_obj_t ctx, mp_obj_t pending, mp_int_t t) {
    mp_obj_t *c = ((mp_obj_tuple_t *)MP_OBJ_TO_PTR(ctx))->items;
    mp_obj_t g = c[0], link = c[1];
    mp_obj_dict_store(g, MP_OBJ_NEW_QSTR(MP_QSTR__wrote), mp_const_false);
    mp_obj_t syncs = class_get(link, MP_QSTR_syncs);
    dispatch(ctx, pending);
    if (!mp_obj_equal(class_get(link, MP_QSTR_syncs), syncs)) {
        return 3;
    }
    mp_obj_t woke_fn = mp_load_attr(global(g, MP_QSTR__link), MP_QSTR_woke);
    bool woke = woke_fn != mp_const_none && mp_obj_is_true(mp_call_function_0(woke_fn));
    if (mp_obj_is_true(global(g, MP_QSTR__wrote)) || woke) {
        if (mp_obj_is_true(global(g, MP_QSTR__lockstep))) {
            mp_obj_dict_store(g, MP_OBJ_NEW_QSTR(MP_QSTR__now), mp_obj_new_int(t));
        }
        mp_obj_dict_store(g, MP_OBJ_NEW_QSTR(MP_QSTR__horizon), global(g, MP_QSTR__now));
        return woke ? 2 : 1;
    }
    return 0;
}

// -- EDGES: encoder edges as segments (_hilframe.EDGE_SEG_FMT), expanded here --------------

#define EDGES_MAX 64  // segments in one EDGES (host/rig/inputs.py, MAX_SEGMENTS)
#define EDGES_HEAD 10  // "<QH": base, segments
#define SEG_LEN 51  // "<HHBBBQqIQdd"
#define NO_HANDLE 0xFFFF

typedef struct {
    mp_int_t t;  // the next edge's instant
    int64_t n;  // the count before it
    uint32_t left;  // edges still to come
    uint16_t h[2];  // the channels' handles (NO_HANDLE: wired to no pin)
    uint8_t mask, bits[2];  // each channel's level by count & mask
    int step;  // +1, -1
    int64_t t0;
    double p0, rate;
} seg_t;

static uint64_t get_u64(const uint8_t *b) {
    return (uint64_t)get_u32(b) | (uint64_t)get_u32(b + 4) << 32;
}

static double get_f64(const uint8_t *b) {
    uint64_t u = get_u64(b);
    double d;
    memcpy(&d, &u, sizeof(d));
    return d;
}

// When the counter reaches count m (not its first edge): _EdgeCounter.emit's arithmetic, IEEE
// double as CPython's (_hilframe.expand_edges, sim_plant/edge_window.py).
static mp_int_t seg_time(const seg_t *s, int64_t m) {
    double x = s->step > 0 ? ((double)m - s->p0) / s->rate : (s->p0 - (double)(m + 1)) / -s->rate;
    return (mp_int_t)(s->t0 + (int64_t)ceil(x));
}

static size_t parse_edges_buf(const uint8_t *b, size_t len, mp_int_t base, seg_t *seg) {
    if (len < EDGES_HEAD) {
        mp_raise_ValueError(MP_ERROR_TEXT("EDGES shorter than its segments"));
    }
    size_t n = b[8] | b[9] << 8;
    if (n > EDGES_MAX || len < EDGES_HEAD + n * SEG_LEN || (mp_int_t)get_u64(b) != base) {
        mp_raise_ValueError(MP_ERROR_TEXT("EDGES not its STATE's"));
    }
    for (size_t k = 0; k < n; k++) {
        const uint8_t *c = b + EDGES_HEAD + k * SEG_LEN;
        seg_t *s = &seg[k];
        s->h[0] = c[0] | c[1] << 8;
        s->h[1] = c[2] | c[3] << 8;
        s->mask = c[4];
        s->bits[0] = c[5];
        s->bits[1] = c[6];
        s->t = (mp_int_t)get_u64(c + 7);
        s->n = (int64_t)get_u64(c + 15);
        s->left = get_u32(c + 23);
        s->t0 = (int64_t)get_u64(c + 27);
        s->p0 = get_f64(c + 35);
        s->rate = get_f64(c + 43);
        s->step = s->rate > 0.0 ? 1 : -1;
    }
    return n;
}

static size_t parse_edges(mp_obj_t edges, mp_int_t base, seg_t *seg) {
    mp_buffer_info_t buf;
    mp_get_buffer_raise(edges, &buf, MP_BUFFER_READ);
    return parse_edges_buf(buf.buf, buf.len, base, seg);
}

// apply_state's loop over a STATE's payload (p, of buf_len bytes) and its segments.
static mp_int_t apply_core(const uint8_t *p, size_t buf_len, mp_obj_list_t *cur, mp_int_t base, mp_int_t t_end, mp_int_t n,
    mp_obj_t handles, mp_obj_t pin_type, mp_obj_t pending, mp_obj_t watch, mp_obj_t ctx, mp_obj_t globals,
    seg_t *seg, size_t n_seg) {
    queue_depth = mp_obj_get_int(mp_load_attr(((mp_obj_tuple_t *)MP_OBJ_TO_PTR(ctx))->items[1], MP_QSTR_depth));
    shim_globals = ((mp_obj_tuple_t *)MP_OBJ_TO_PTR(ctx))->items[0];
    bool watching = mp_obj_is_true(watch);
    apply_clean = false;  // (the firmware ran before this call: its compute is taken first)
    size_t off = MP_OBJ_SMALL_INT_VALUE(cur->items[0]);
    mp_int_t i = MP_OBJ_SMALL_INT_VALUE(cur->items[1]);
    mp_int_t group_t = -1;
    bool hit = false;
    mp_int_t stop = 0;
    for (;;) {
        // the next edge of the segments (at one instant, the first segment's), up to t_end
        size_t si = n_seg;
        mp_int_t ts = 0;
        for (size_t k = 0; k < n_seg; k++) {
            if (seg[k].left && (si == n_seg || seg[k].t < ts)) {
                si = k;
                ts = seg[k].t;
            }
        }
        mp_int_t tc = 0;
        if (i < n) {
            if (off + CHANGE_LEN > buf_len) {
                mp_raise_ValueError(MP_ERROR_TEXT("STATE shorter than its changes"));
            }
            tc = base + (mp_int_t)get_u32(p + off);
        }
        if (si < n_seg && (i >= n || ts <= tc)) {  // (an instant's encoder edges before its other changes)
            seg_t *s = &seg[si];
            int64_t m = s->n + s->step;
            int a = s->bits[0] >> (m & s->mask) & 1;
            int ch = a != (s->bits[0] >> (s->n & s->mask) & 1) ? 0 : 1;
            int level = ch ? s->bits[1] >> (m & s->mask) & 1 : a;
            mp_int_t h = s->h[ch];
            s->n = m;
            if (--s->left) {
                s->t = seg_time(s, m + s->step);
            }
            if (ts > t_end) {
                mp_raise_ValueError(MP_ERROR_TEXT("EDGES past its STATE's end"));
            }
            if (h == NO_HANDLE) {
                continue;  // (a channel wired to no pin: no change, as the host sends none)
            }
            if (ts != group_t) {
                if (group_t >= 0 && pending_any(pending)) {
                    stop = handlers_wrote(ctx, pending, group_t);
                    if (stop) {
                        break;
                    }
                }
                group_t = ts;
                if (globals != mp_const_none) {
                    mp_obj_dict_store(globals, MP_OBJ_NEW_QSTR(MP_QSTR__now), mp_obj_new_int(ts));
                }
            }
            mp_obj_t obj = mp_obj_subscr(handles, MP_OBJ_NEW_SMALL_INT(h), MP_OBJ_SENTINEL);
            apply_one(obj, pin_type, 0, MP_OBJ_NEW_SMALL_INT(level), MP_OBJ_NEW_SMALL_INT(0), pending);
            if (watching && mp_obj_is_true(mp_binary_op(MP_BINARY_OP_CONTAINS, watch, MP_OBJ_NEW_SMALL_INT(h)))) {
                hit = true;
            }
            continue;
        }
        if (i >= n) {
            break;
        }
        const uint8_t *c = p + off;
        mp_int_t t = tc;
        if (t > t_end) {
            break;  // held by the caller (the host's lookahead)
        }
        mp_int_t h = c[4] | c[5] << 8;
        int kind = c[6];
        mp_int_t value = (int32_t)get_u32(c + 7);
        uint32_t extra_u = get_u32(c + 11);
        off += CHANGE_LEN;
        mp_obj_t extra;
        if (kind == CH_BYTES) {
            if (value < 0 || off + value > buf_len) {
                mp_raise_ValueError(MP_ERROR_TEXT("STATE shorter than its changes"));
            }
            extra = mp_obj_new_bytes(p + off, value);
            off += value;
        } else {
            extra = mp_obj_new_int_from_uint(extra_u);
        }
        if (t != group_t) {
            if (group_t >= 0 && pending_any(pending)) {
                stop = handlers_wrote(ctx, pending, group_t);
                if (stop) {
                    break;
                }
            }
            group_t = t;
            if (globals != mp_const_none) {
                mp_obj_dict_store(globals, MP_OBJ_NEW_QSTR(MP_QSTR__now), mp_obj_new_int(t));
            }
        }
        mp_obj_t obj = mp_obj_subscr(handles, MP_OBJ_NEW_SMALL_INT(h), MP_OBJ_SENTINEL);
        apply_one(obj, pin_type, kind, mp_obj_new_int(value), extra, pending);
        if (watching && mp_obj_is_true(mp_binary_op(MP_BINARY_OP_CONTAINS, watch, MP_OBJ_NEW_SMALL_INT(h)))) {
            hit = true;
        }
        i++;
    }
    if (!stop && group_t >= 0 && pending_any(pending)) {
        stop = handlers_wrote(ctx, pending, group_t);
    }
    cur->items[0] = MP_OBJ_NEW_SMALL_INT(off);
    cur->items[1] = MP_OBJ_NEW_SMALL_INT(i);
    cur->items[2] = mp_obj_new_bool(hit);
    return stop;
}

static mp_obj_t apply_state(size_t n_args, const mp_obj_t *args) {
    mp_buffer_info_t buf;
    mp_get_buffer_raise(args[0], &buf, MP_BUFFER_READ);
    mp_int_t base = mp_obj_get_int(args[2]);
    seg_t seg[EDGES_MAX];
    size_t n_seg = n_args > 11 && args[11] != mp_const_none ? parse_edges(args[11], base, seg) : 0;
    return MP_OBJ_NEW_SMALL_INT(apply_core(buf.buf, buf.len, MP_OBJ_TO_PTR(args[1]), base, mp_obj_get_int(args[3]),
        mp_obj_get_int(args[4]), args[5], args[6], args[7], args[8], args[9], args[10], seg, n_seg));
}
static MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN(apply_state_obj, 11, 12, apply_state);

// merge_edges(edges, base, changes): a STATE's changes (a list of (t, handle, kind, value,
// extra) in time order) with its EDGES' edges merged in, as a new list: what _hil._apply_state
// applies where apply_state cannot run (a callback, IRQs off, a C call), as
// _hilframe.expand_edges and the merge after it make it (an instant's edges first, at one
// instant in the segments' order; an edge of a channel wired to no pin left out), in C.
static mp_obj_t merge_edges(mp_obj_t edges, mp_obj_t base_in, mp_obj_t changes) {
    seg_t seg[EDGES_MAX];
    size_t n_seg = parse_edges(edges, mp_obj_get_int(base_in), seg);
    size_t n_ch;
    mp_obj_t *ch;
    mp_obj_get_array(changes, &n_ch, &ch);
    size_t room = n_ch;
    for (size_t k = 0; k < n_seg; k++) {
        room += seg[k].left;
    }
    mp_obj_t out = mp_obj_new_list(room, NULL);
    mp_obj_list_t *list = MP_OBJ_TO_PTR(out);
    size_t j = 0, ci = 0;
    mp_int_t tc = 0;
    bool have_tc = false;
    for (;;) {
        size_t si = n_seg;
        mp_int_t ts = 0;
        for (size_t k = 0; k < n_seg; k++) {
            if (seg[k].left && (si == n_seg || seg[k].t < ts)) {
                si = k;
                ts = seg[k].t;
            }
        }
        if (ci < n_ch && !have_tc) {
            mp_obj_t *c;
            mp_obj_get_array_fixed_n(ch[ci], 5, &c);
            tc = mp_obj_get_int(c[0]);
            have_tc = true;
        }
        if (si < n_seg && (ci >= n_ch || ts <= tc)) {
            seg_t *s = &seg[si];
            int64_t m = s->n + s->step;
            int a = s->bits[0] >> (m & s->mask) & 1;
            int which = a != (s->bits[0] >> (s->n & s->mask) & 1) ? 0 : 1;
            int level = which ? s->bits[1] >> (m & s->mask) & 1 : a;
            mp_int_t h = s->h[which];
            s->n = m;
            if (--s->left) {
                s->t = seg_time(s, m + s->step);
            }
            if (h != NO_HANDLE) {
                mp_obj_t item[5] = {mp_obj_new_int(ts), MP_OBJ_NEW_SMALL_INT(h), MP_OBJ_NEW_SMALL_INT(0),
                                    MP_OBJ_NEW_SMALL_INT(level), MP_OBJ_NEW_SMALL_INT(0)};
                list->items[j++] = mp_obj_new_tuple(5, item);
            }
        } else if (ci < n_ch) {
            list->items[j++] = ch[ci++];
            have_tc = false;
        } else {
            break;
        }
    }
    list->len = j;  // (the edges of channels wired to no pin: none)
    return out;
}
static MP_DEFINE_CONST_FUN_OBJ_3(merge_edges_obj, merge_edges);

// -- the link: the firmware's side of an exchange, in C ---------------------------------
//
// link(fd, host_gone): the link's frames over the host's pty (fd), with no allocation per
// exchange: frames are encoded into a buffer of this module's and written from it, read
// from the fd into another, their CRC-32 taken here, a STATE kept (with its EDGES) in a
// buffer of its own and applied from there (apply_core, in one pass). Exactly the bytes
// and the decoding of _hil._framed_out and _hilframe.Decoder (the same frames accepted,
// the same counted: the pure path is the reference, host/tests/test_hilfast.py). Made once
// (the shim's link, before the firmware runs); its methods are held by the shim's link only:
//   queue(type, payload), flush(): as _hil._framed_out's;
//   recv(): the next good frame (type, seq, payload), or None once a frame was damaged
//     or lost (the shim raises LinkDamaged with counters());
//   wait(hdr, t_now[, t_until, compute_us, watch]): with its arguments, WAIT sent first; then the frames
//     read until the STATE for t_now: None (the STATE held, hdr = [base, t_end, horizon,
//     count, paused_us]); a frame of another kind is returned as recv returns it (the
//     shim handles it and calls wait(hdr, t_now) again); 0 once damaged. An EDGES is kept
//     for the STATE after it, a STATE for another instant dropped;
//   apply(cur, handles, pin_type, pending, watch, ctx, g): apply_state over the held STATE
//     (and its EDGES); state(), edges(): them as bytes (None: no EDGES), for the pure loop;
//     has_edges(): whether it came with an EDGES;
//   bind(hdr, cur, handles, pending, ctx, g, shim_g), then exchange(t_until, compute_us,
//     watch) and run(watch, pin_type): wait and apply with what bind gave (the shim's _sync:
//     fewer arguments, a frame of its own that fits the C stack's), exchange's MemoryError
//     for a frame of another kind returned as -1;
//   out(t, handle, attr, value): an OUT queued, as _hil.send_out packs it (False: a value
//     that is not a small int, left to struct.pack);
//   room(n): whether n bytes can be had from the heap (taken and given back at once: no
//     garbage), as _hil.make_room's probe; counters(): (frames, bad_crc, bad_length,
//     truncated, seq_gaps, duplicates).

#define SOF 0xA5
#define HEADER_LEN 5  // SOF, type, seq, length (u16)
#define CRC_LEN 4
#define MAX_PAYLOAD 4096
#define FRAME_MAX (HEADER_LEN + MAX_PAYLOAD + CRC_LEN)
#define T_OUT 0x03
#define T_WAIT 0x04
#define OUT_LEN 15  // "<QHBi"
#define T_STATE 0x82
#define T_EDGES 0x87
#define STATE_HEAD 26  // "<QQQH"
#define WAIT_HEAD 20  // "<QQI"
#define IN_SIZE (4 * FRAME_MAX)
#define OUT_SIZE (2 * FRAME_MAX)

static uint32_t crc_t[8][256];  // CRC-32 (zlib's), eight bytes a step
static bool crc_ready;

static void crc_init(void) {
    for (uint32_t i = 0; i < 256; i++) {
        uint32_t c = i;
        for (int k = 0; k < 8; k++) {
            c = (c >> 1) ^ (0xEDB88320 & -(c & 1));
        }
        crc_t[0][i] = c;
    }
    for (uint32_t i = 0; i < 256; i++) {
        for (int k = 1; k < 8; k++) {
            crc_t[k][i] = (crc_t[k - 1][i] >> 8) ^ crc_t[0][crc_t[k - 1][i] & 0xFF];
        }
    }
    crc_ready = true;
}

static uint32_t crc32_of(const uint8_t *b, size_t n) {
    uint32_t c = 0xFFFFFFFF;
    while (n >= 8) {
        c ^= get_u32(b);
        uint32_t hi = get_u32(b + 4);
        c = crc_t[7][c & 0xFF] ^ crc_t[6][(c >> 8) & 0xFF] ^ crc_t[5][(c >> 16) & 0xFF] ^ crc_t[4][c >> 24]
            ^ crc_t[3][hi & 0xFF] ^ crc_t[2][(hi >> 8) & 0xFF] ^ crc_t[1][(hi >> 16) & 0xFF] ^ crc_t[0][hi >> 24];
        b += 8;
        n -= 8;
    }
    while (n--) {
        c = crc_t[0][(c ^ *b++) & 0xFF] ^ (c >> 8);
    }
    return c ^ 0xFFFFFFFF;
}

static void put_u32(uint8_t *b, uint32_t v) {
    b[0] = v;
    b[1] = v >> 8;
    b[2] = v >> 16;
    b[3] = v >> 24;
}

static void put_u64(uint8_t *b, uint64_t v) {
    put_u32(b, (uint32_t)v);
    put_u32(b + 4, (uint32_t)(v >> 32));
}

static mp_obj_t int_u64(uint64_t v) {
    return v <= (uint64_t)MP_SMALL_INT_MAX ? MP_OBJ_NEW_SMALL_INT((mp_int_t)v) : mp_obj_new_int_from_ull(v);
}

static int link_fd = -1;
static mp_obj_t link_host_gone;  // _hil.HostGone (held by the _hil module)
static uint8_t in_buf[IN_SIZE];
static size_t in_pos, in_len;
static uint8_t out_buf[OUT_SIZE];
static size_t out_len;
static uint8_t out_seq;
static int expect_seq = -1;
static size_t n_frames, n_bad_crc, n_bad_length, n_truncated, n_seq_gaps, n_duplicates, n_damaged;
static uint8_t state_buf[MAX_PAYLOAD];
static size_t state_len;
static mp_int_t state_base, state_t_end, state_n;
static uint8_t edges_buf[MAX_PAYLOAD];
static int edges_len = -1;  // the EDGES read before the coming STATE (-1: none)
static int state_edges = -1;  // the held STATE's EDGES (its length in edges_buf; -1: none)

typedef struct {
    int type, seq;
    size_t off, len, next;  // the payload in in_buf, where the decoder goes on after it
} frame_t;

static void link_gone(void) {
    nlr_raise(mp_call_function_1(link_host_gone, mp_obj_new_str("plant link closed", 17)));
}

// Decoder.next up to taking the frame: true with f filled (link_take commits it); false when
// no whole frame is there. Bad lengths, bad CRCs and duplicates are counted and skipped.
static bool link_next(frame_t *f) {
    size_t pos = in_pos;
    for (;;) {
        const uint8_t *s = pos < in_len ? memchr(in_buf + pos, SOF, in_len - pos) : NULL;
        size_t i = s != NULL ? (size_t)(s - in_buf) : in_len;
        if (i + HEADER_LEN > in_len) {
            in_pos = i;
            return false;
        }
        size_t n = in_buf[i + 3] | in_buf[i + 4] << 8;
        if (n > MAX_PAYLOAD) {
            n_bad_length++;
            n_damaged++;
            pos = i + 1;
            continue;
        }
        size_t end = i + HEADER_LEN + n;
        if (end + CRC_LEN > in_len) {
            in_pos = i;
            return false;
        }
        if (crc32_of(in_buf + i + 1, end - i - 1) != get_u32(in_buf + end)) {
            n_bad_crc++;
            n_damaged++;
            pos = i + 1;
            continue;
        }
        int seq = in_buf[i + 2];
        if (expect_seq >= 0 && seq == ((expect_seq - 1) & 0xFF)) {  // the last frame again
            in_pos = pos = end + CRC_LEN;
            n_duplicates++;
            continue;
        }
        in_pos = i;
        f->type = in_buf[i + 1];
        f->seq = seq;
        f->off = i + HEADER_LEN;
        f->len = n;
        f->next = end + CRC_LEN;
        return true;
    }
}

static void link_take(const frame_t *f) {
    in_pos = f->next;
    if (expect_seq >= 0 && f->seq != expect_seq) {
        n_seq_gaps++;
        n_damaged++;
    }
    n_frames++;
    expect_seq = (f->seq + 1) & 0xFF;
}

// More bytes from the host: _framed_in's poll of a second, then a read (HostGone when
// the pty closed); a partial frame that stopped arriving for that second is dropped.
static void link_fill(void) {
    for (;;) {
        struct pollfd pfd = {link_fd, POLLIN, 0};
        int r = poll(&pfd, 1, 1000);
        if (r < 0) {
            if (errno == EINTR) {
                mp_handle_pending(true);
                continue;
            }
            mp_raise_OSError(errno);
        }
        if (r == 0) {
            if (in_len > in_pos) {  // (Decoder.expire)
                n_truncated++;
                n_damaged++;
                in_pos++;
            }
            return;
        }
        if (pfd.revents & (POLLHUP | POLLERR)) {
            link_gone();
        }
        if (in_pos == in_len) {
            in_pos = in_len = 0;
        } else if (in_len + FRAME_MAX > IN_SIZE) {
            memmove(in_buf, in_buf + in_pos, in_len - in_pos);
            in_len -= in_pos;
            in_pos = 0;
        }
        ssize_t got = read(link_fd, in_buf + in_len, IN_SIZE - in_len);
        if (got < 0 && errno == EINTR) {
            mp_handle_pending(true);
            continue;
        }
        if (got <= 0) {
            link_gone();
        }
        in_len += got;
        return;
    }
}

static void link_flush(void) {
    const uint8_t *b = out_buf;
    size_t n = out_len;
    while (n) {
        ssize_t r = write(link_fd, b, n);
        if (r < 0) {
            if (errno == EINTR) {
                mp_handle_pending(true);
                continue;
            }
            if (errno == EAGAIN) {
                struct pollfd pfd = {link_fd, POLLOUT, 0};
                poll(&pfd, 1, 1000);
                continue;
            }
            out_len = 0;
            mp_raise_OSError(errno);
        }
        b += r;
        n -= r;
    }
    out_len = 0;
}

// One frame into the out buffer (_hilframe.encode; flushed first when it has no room).
static uint8_t *link_frame(int type, size_t n) {
    if (n > MAX_PAYLOAD) {
        mp_raise_msg_varg(&mp_type_ValueError, MP_ERROR_TEXT("payload of %d bytes exceeds %d"), (int)n, MAX_PAYLOAD);
    }
    if (out_len + HEADER_LEN + n + CRC_LEN > OUT_SIZE) {
        link_flush();
    }
    uint8_t *f = out_buf + out_len;
    f[0] = SOF;
    f[1] = type;
    f[2] = out_seq;
    f[3] = n & 0xFF;
    f[4] = n >> 8;
    return f + HEADER_LEN;
}

static void link_sealed(size_t n) {  // the frame link_frame began, its n bytes written: its CRC
    uint8_t *f = out_buf + out_len;
    put_u32(f + HEADER_LEN + n, crc32_of(f + 1, n + HEADER_LEN - 1));
    out_len += HEADER_LEN + n + CRC_LEN;
    out_seq++;
}

typedef struct {
    mp_obj_base_t base;
} link_obj_t;

static mp_obj_t link_queue(mp_obj_t self, mp_obj_t type, mp_obj_t payload) {
    (void)self;
    mp_buffer_info_t buf;
    mp_get_buffer_raise(payload, &buf, MP_BUFFER_READ);
    uint8_t *p = link_frame(mp_obj_get_int(type), buf.len);
    memcpy(p, buf.buf, buf.len);
    link_sealed(buf.len);
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_3(link_queue_obj, link_queue);

static mp_obj_t link_flush_py(mp_obj_t self) {
    (void)self;
    link_flush();
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_1(link_flush_obj, link_flush_py);

// The frame as recv returns it, taken only once its objects are made (a MemoryError leaves
// it to be read again, as the Decoder's copy does).
static mp_obj_t link_tuple(const frame_t *f) {
    mp_obj_t item[3] = {MP_OBJ_NEW_SMALL_INT(f->type), MP_OBJ_NEW_SMALL_INT(f->seq), mp_obj_new_bytes(in_buf + f->off, f->len)};
    mp_obj_t t = mp_obj_new_tuple(3, item);
    link_take(f);
    return t;
}

static mp_obj_t link_recv(mp_obj_t self) {
    (void)self;
    for (;;) {
        frame_t f;
        bool got = link_next(&f);
        if (n_damaged) {  // (the good frame after a damaged one is taken and counted, as the Decoder does)
            if (got) {
                link_take(&f);
            }
            return mp_const_none;
        }
        if (got) {
            mp_obj_t t = link_tuple(&f);
            return n_damaged ? mp_const_none : t;  // (a gap before it: taken, then the run stops)
        }
        link_fill();
    }
}
static MP_DEFINE_CONST_FUN_OBJ_1(link_recv_obj, link_recv);

static mp_obj_t link_wait(size_t n_args, const mp_obj_t *args) {
    mp_obj_list_t *hdr = MP_OBJ_TO_PTR(args[1]);
    mp_int_t t_now = mp_obj_get_int(args[2]);
    if (n_args > 3) {  // the WAIT (_hil._sync's: F.WAIT_FMT, then F.WATCH_FMT a watched handle)
        size_t n_watch = 0;
        if (args[5] != mp_const_none && mp_obj_is_true(args[5])) {
            n_watch = mp_obj_get_int(mp_obj_len(args[5]));
        }
        uint8_t *p = link_frame(T_WAIT, WAIT_HEAD + 2 * n_watch);
        put_u64(p, t_now);
        put_u64(p + 8, mp_obj_is_small_int(args[3]) ? (uint64_t)MP_OBJ_SMALL_INT_VALUE(args[3])
                                                     : (uint64_t)mp_obj_int_get_uint_checked(args[3]));  // (FOREVER_US: a big int)
        put_u32(p + 16, mp_obj_get_int(args[4]));
        if (n_watch) {
            mp_obj_iter_buf_t iter_buf;
            mp_obj_t it = mp_getiter(args[5], &iter_buf), h;
            size_t k = 0;
            while ((h = mp_iternext(it)) != MP_OBJ_STOP_ITERATION && k < n_watch) {
                mp_int_t v = mp_obj_get_int(h);
                p[WAIT_HEAD + 2 * k] = v & 0xFF;
                p[WAIT_HEAD + 2 * k + 1] = (v >> 8) & 0xFF;
                k++;
            }
        }
        link_sealed(WAIT_HEAD + 2 * n_watch);
        link_flush();
        edges_len = -1;
    }
    for (;;) {
        frame_t f;
        bool got = link_next(&f);
        if (n_damaged) {
            if (got) {
                link_take(&f);
            }
            return MP_OBJ_NEW_SMALL_INT(0);
        }
        if (!got) {
            link_fill();
            continue;
        }
        const uint8_t *p = in_buf + f.off;  // (there until the next link_fill)
        if (f.type != T_STATE && f.type != T_EDGES) {
            mp_obj_t t = link_tuple(&f);
            return n_damaged ? MP_OBJ_NEW_SMALL_INT(0) : t;
        }
        link_take(&f);
        if (n_damaged) {  // (a gap before it)
            return MP_OBJ_NEW_SMALL_INT(0);
        }
        if (f.type == T_STATE) {
            if (f.len < STATE_HEAD) {
                mp_raise_ValueError(MP_ERROR_TEXT("STATE shorter than its header"));
            }
            if ((mp_int_t)get_u64(p) != t_now) {
                edges_len = -1;  // (a STATE for another WAIT is stale: a Ctrl-C cut that wait short)
                continue;
            }
            memcpy(state_buf, p, f.len);
            state_len = f.len;
            state_base = (mp_int_t)get_u64(p);
            state_t_end = (mp_int_t)get_u64(p + 8);
            state_n = p[24] | p[25] << 8;
            state_edges = edges_len >= (int)EDGES_HEAD && (mp_int_t)get_u64(edges_buf) == state_base ? edges_len : -1;
            edges_len = -1;
            hdr->items[0] = int_u64(state_base);
            hdr->items[1] = int_u64(state_t_end);
            hdr->items[2] = int_u64(get_u64(p + 16));
            hdr->items[3] = MP_OBJ_NEW_SMALL_INT(state_n);
            hdr->items[4] = int_u64(get_u64(p + f.len - 8));
            return mp_const_none;
        }
        memcpy(edges_buf, p, f.len);  // (an EDGES: for the STATE after it)
        edges_len = f.len;
    }
}
static MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN(link_wait_obj, 3, 6, link_wait);

static mp_obj_t link_apply(size_t n_args, const mp_obj_t *args) {
    (void)n_args;
    seg_t seg[EDGES_MAX];
    size_t n_seg = state_edges >= 0 ? parse_edges_buf(edges_buf, state_edges, state_base, seg) : 0;
    return MP_OBJ_NEW_SMALL_INT(apply_core(state_buf, state_len, MP_OBJ_TO_PTR(args[1]), state_base, state_t_end, state_n,
        args[2], args[3], args[4], args[5], args[6], args[7], seg, n_seg));
}
static MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN(link_apply_obj, 8, 8, link_apply);

// bind(hdr, cur, handles, pending, ctx, g, shim_g): what exchange and run take each time (the
// shim holds each: _Link.hdr, _Link.cur, _hil._handles, _hil._pending, _Link.ctx, _Link.g, and
// _hil's globals, whose _now is the WAIT's instant).
static mp_obj_t bound[7];
enum { B_HDR, B_CUR, B_HANDLES, B_PENDING, B_CTX, B_G, B_SHIM };

static mp_obj_t link_bind(size_t n_args, const mp_obj_t *args) {
    for (size_t i = 0; i < 7; i++) {
        bound[i] = args[i + 1];
    }
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN(link_bind_obj, 8, 8, link_bind);

// exchange(t_until, compute_us, watch): wait(hdr, _now, t_until, compute_us, watch) with what
// bind gave, save that a frame of another kind whose objects could not be made (a MemoryError)
// is -1: the shim frees its reserve and reads again (wait(hdr, _now)).
static mp_obj_t link_exchange(size_t n_args, const mp_obj_t *args) {
    (void)n_args;
    mp_obj_t a[6] = {args[0], bound[B_HDR], mp_obj_dict_get(bound[B_SHIM], MP_OBJ_NEW_QSTR(MP_QSTR__now)), args[1], args[2], args[3]};
    nlr_buf_t nlr;
    if (nlr_push(&nlr) == 0) {
        mp_obj_t r = link_wait(6, a);
        nlr_pop();
        return r;
    }
    if (mp_obj_is_subclass_fast(MP_OBJ_FROM_PTR(((mp_obj_base_t *)nlr.ret_val)->type), MP_OBJ_FROM_PTR(&mp_type_MemoryError))) {
        return MP_OBJ_NEW_SMALL_INT(-1);
    }
    nlr_jump(nlr.ret_val);
}
static MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN(link_exchange_obj, 4, 4, link_exchange);

// run(watch, pin_type): apply(cur, handles, pin_type, pending, watch, ctx, g) with what bind gave,
// cur set to [STATE_LEN, 0, False] first.
static mp_obj_t link_run(mp_obj_t self, mp_obj_t watch, mp_obj_t pin_type) {
    mp_obj_list_t *cur = MP_OBJ_TO_PTR(bound[B_CUR]);
    cur->items[0] = MP_OBJ_NEW_SMALL_INT(STATE_HEAD);
    cur->items[1] = MP_OBJ_NEW_SMALL_INT(0);
    cur->items[2] = mp_const_false;
    mp_obj_t a[8] = {self, bound[B_CUR], bound[B_HANDLES], pin_type, bound[B_PENDING], watch, bound[B_CTX], bound[B_G]};
    return link_apply(8, a);
}
static MP_DEFINE_CONST_FUN_OBJ_3(link_run_obj, link_run);

static mp_obj_t link_state(mp_obj_t self) {
    (void)self;
    return mp_obj_new_bytes(state_buf, state_len);
}
static MP_DEFINE_CONST_FUN_OBJ_1(link_state_obj, link_state);

static mp_obj_t link_has_edges(mp_obj_t self) {
    (void)self;
    return mp_obj_new_bool(state_edges >= 0);
}
static MP_DEFINE_CONST_FUN_OBJ_1(link_has_edges_obj, link_has_edges);

// out(t, handle, attr, value): an OUT queued (_hilframe.OUT_FMT, as _hil.send_out packs it),
// True; False (nothing queued) for a value that is not a small int (struct.pack's way with
// it is the shim's to take).
static mp_obj_t link_out(size_t n_args, const mp_obj_t *args) {
    (void)n_args;
    if (!mp_obj_is_small_int(args[4]) || !mp_obj_is_small_int(args[1])) {
        return mp_const_false;
    }
    uint8_t *p = link_frame(T_OUT, OUT_LEN);
    put_u64(p, (uint64_t)MP_OBJ_SMALL_INT_VALUE(args[1]));
    mp_int_t h = mp_obj_get_int(args[2]);
    p[8] = h & 0xFF;
    p[9] = (h >> 8) & 0xFF;
    p[10] = mp_obj_get_int(args[3]) & 0xFF;
    put_u32(p + 11, (uint32_t)MP_OBJ_SMALL_INT_VALUE(args[4]));
    link_sealed(OUT_LEN);
    return mp_const_true;
}
static MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN(link_out_obj, 5, 5, link_out);

static mp_obj_t link_edges(mp_obj_t self) {
    (void)self;
    return state_edges >= 0 ? mp_obj_new_bytes(edges_buf, state_edges) : mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_1(link_edges_obj, link_edges);

// (First: whether the heap's blocks past the highest in use, py/gc.c's gc_last_used_block, hold
// n bytes: then gc_alloc would find them, with no search through the heap's holes.)
static mp_obj_t link_room(mp_obj_t self, mp_obj_t n) {
    (void)self;
    const mp_state_mem_area_t *area = &MP_STATE_MEM(area);
    size_t blocks = area->gc_alloc_table_byte_len * 4;  // (py/gc.c: BLOCKS_PER_ATB)
    size_t need = (mp_obj_get_int(n) + MICROPY_BYTES_PER_GC_BLOCK - 1) / MICROPY_BYTES_PER_GC_BLOCK;
    if (area->gc_last_used_block + 1 + need <= blocks) {
        return mp_const_true;
    }
    void *b = gc_alloc(mp_obj_get_int(n), 0);
    if (b == NULL) {
        return mp_const_false;
    }
    gc_free(b);
    return mp_const_true;
}
static MP_DEFINE_CONST_FUN_OBJ_2(link_room_obj, link_room);

static mp_obj_t link_counters(mp_obj_t self) {
    (void)self;
    mp_obj_t item[6] = {MP_OBJ_NEW_SMALL_INT(n_frames), MP_OBJ_NEW_SMALL_INT(n_bad_crc), MP_OBJ_NEW_SMALL_INT(n_bad_length),
                        MP_OBJ_NEW_SMALL_INT(n_truncated), MP_OBJ_NEW_SMALL_INT(n_seq_gaps), MP_OBJ_NEW_SMALL_INT(n_duplicates)};
    return mp_obj_new_tuple(6, item);
}
static MP_DEFINE_CONST_FUN_OBJ_1(link_counters_obj, link_counters);

static const mp_rom_map_elem_t link_locals_table[] = {
    {MP_ROM_QSTR(MP_QSTR_queue), MP_ROM_PTR(&link_queue_obj)},
    {MP_ROM_QSTR(MP_QSTR_flush), MP_ROM_PTR(&link_flush_obj)},
    {MP_ROM_QSTR(MP_QSTR_recv), MP_ROM_PTR(&link_recv_obj)},
    {MP_ROM_QSTR(MP_QSTR_wait), MP_ROM_PTR(&link_wait_obj)},
    {MP_ROM_QSTR(MP_QSTR_apply), MP_ROM_PTR(&link_apply_obj)},
    {MP_ROM_QSTR(MP_QSTR_state), MP_ROM_PTR(&link_state_obj)},
    {MP_ROM_QSTR(MP_QSTR_edges), MP_ROM_PTR(&link_edges_obj)},
    {MP_ROM_QSTR(MP_QSTR_has_edges), MP_ROM_PTR(&link_has_edges_obj)},
    {MP_ROM_QSTR(MP_QSTR_out), MP_ROM_PTR(&link_out_obj)},
    {MP_ROM_QSTR(MP_QSTR_bind), MP_ROM_PTR(&link_bind_obj)},
    {MP_ROM_QSTR(MP_QSTR_exchange), MP_ROM_PTR(&link_exchange_obj)},
    {MP_ROM_QSTR(MP_QSTR_run), MP_ROM_PTR(&link_run_obj)},
    {MP_ROM_QSTR(MP_QSTR_room), MP_ROM_PTR(&link_room_obj)},
    {MP_ROM_QSTR(MP_QSTR_counters), MP_ROM_PTR(&link_counters_obj)},
};
static MP_DEFINE_CONST_DICT(link_locals, link_locals_table);
static MP_DEFINE_CONST_OBJ_TYPE(link_type, MP_QSTR_link, MP_TYPE_FLAG_NONE, locals_dict, &link_locals);

static mp_obj_t link_new(mp_obj_t fd, mp_obj_t host_gone) {
    if (link_fd >= 0) {
        mp_raise_msg(&mp_type_RuntimeError, MP_ERROR_TEXT("the link is open"));
    }
    if (!crc_ready) {
        crc_init();
    }
    link_fd = mp_obj_get_int(fd);
    link_host_gone = host_gone;
    link_obj_t *o = mp_obj_malloc(link_obj_t, &link_type);
    return MP_OBJ_FROM_PTR(o);
}
static MP_DEFINE_CONST_FUN_OBJ_2(link_new_obj, link_new);

// -- machine.Pin.value() ---------------------------------------------------------------

// pin_setup(value_py, out_mode, g): machine.Pin.value becomes pin_value, which answers in C
// what machine.py's Pin.value (value_py, kept by the class as _value_py) answers without a
// look at the clock: an output's latch, and an input's level inside a handler (_hil's
// _dispatching, in its globals g); every other call goes to value_py, as the Python method.
// With poll_reads (machine._POLL_READS), an input's read in the main program is C too, when it
// is what _hil.observe does without a look at the host: in lockstep, no callback left queued,
// no MCU time (observe is _hil._observe_free), the clock (after the spin's step) short of the
// horizon and the next Timer; then _now and _spin move, and the pin's count down to a look
// (_pv, _pn, _pr, _pt) as machine.py's Pin.value moves it; its last read goes to Python (_polled).
static mp_obj_t pin_value_py = MP_OBJ_NULL;  // (held by machine.Pin._value_py: alive while the class is)
static mp_obj_t pin_out_mode;
static mp_obj_t pin_shim_globals;  // (held by the _hil module)
static mp_int_t pin_poll_reads;  // 0: an input's main-program read goes to Python
static mp_int_t pin_spin_limit, pin_spin_step;

static mp_obj_t pin_setup(size_t n_args, const mp_obj_t *args) {
    pin_value_py = args[0];
    pin_out_mode = args[1];
    pin_shim_globals = args[2];
    pin_poll_reads = n_args > 3 ? mp_obj_get_int(args[3]) : 0;
    pin_spin_limit = mp_obj_get_int(mp_obj_dict_get(args[2], MP_OBJ_NEW_QSTR(MP_QSTR_SPIN_LIMIT)));
    pin_spin_step = mp_obj_get_int(mp_obj_dict_get(args[2], MP_OBJ_NEW_QSTR(MP_QSTR_SPIN_STEP_US)));
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN(pin_setup_obj, 3, 4, pin_setup);

static mp_map_elem_t *shim_slot(qstr name) {
    mp_obj_dict_t *d = MP_OBJ_TO_PTR(pin_shim_globals);
    return mp_map_lookup(&d->map, MP_OBJ_NEW_QSTR(name), MP_MAP_LOOKUP);
}

// t >= limit (an int: no Timer's due is FOREVER_US, a big int here)
static bool reached(mp_int_t t, mp_obj_t limit) {
    if (mp_obj_is_small_int(limit)) {
        return t >= MP_OBJ_SMALL_INT_VALUE(limit);
    }
    return mp_obj_is_true(mp_binary_op(MP_BINARY_OP_MORE_EQUAL, MP_OBJ_NEW_SMALL_INT(t), limit));
}

// An input's read in the main program, in C (above); MP_OBJ_NULL: Python's steps.
static mp_obj_t pin_read_main(mp_obj_t self) {
    if (!mp_obj_is_obj(self) || !mp_obj_is_instance_type(mp_obj_get_type(self))) {
        return MP_OBJ_NULL;
    }
    mp_map_elem_t *pending = shim_slot(MP_QSTR__pending), *lockstep = shim_slot(MP_QSTR__lockstep);
    mp_map_elem_t *obs = shim_slot(MP_QSTR_observe), *free_obs = shim_slot(MP_QSTR__observe_free);
    mp_map_elem_t *spin = shim_slot(MP_QSTR__spin), *now = shim_slot(MP_QSTR__now);
    mp_map_elem_t *horizon = shim_slot(MP_QSTR__horizon), *due = shim_slot(MP_QSTR__timer_due);
    if (pending == NULL || lockstep == NULL || obs == NULL || free_obs == NULL || spin == NULL || now == NULL
        || horizon == NULL || due == NULL || obs->value != free_obs->value || lockstep->value != mp_const_true
        || !mp_obj_is_type(pending->value, &mp_type_list) || ((mp_obj_list_t *)MP_OBJ_TO_PTR(pending->value))->len
        || !mp_obj_is_small_int(spin->value) || !mp_obj_is_small_int(now->value)) {
        return MP_OBJ_NULL;
    }
    mp_int_t n_spin = MP_OBJ_SMALL_INT_VALUE(spin->value) + 1;
    mp_int_t t = MP_OBJ_SMALL_INT_VALUE(now->value) + (n_spin > pin_spin_limit ? pin_spin_step : 0);
    if (reached(t, horizon->value) || reached(t, due->value)) {
        return MP_OBJ_NULL;  // (a look at the host, or a Timer due)
    }
    mp_obj_instance_t *o = MP_OBJ_TO_PTR(self);
    mp_map_elem_t *level = mp_map_lookup(&o->members, MP_OBJ_NEW_QSTR(MP_QSTR__level), MP_MAP_LOOKUP);
    mp_map_elem_t *pv = mp_map_lookup(&o->members, MP_OBJ_NEW_QSTR(MP_QSTR__pv), MP_MAP_LOOKUP);
    mp_map_elem_t *pn = mp_map_lookup(&o->members, MP_OBJ_NEW_QSTR(MP_QSTR__pn), MP_MAP_LOOKUP);
    mp_map_elem_t *pr = mp_map_lookup(&o->members, MP_OBJ_NEW_QSTR(MP_QSTR__pr), MP_MAP_LOOKUP);
    mp_map_elem_t *pt = mp_map_lookup(&o->members, MP_OBJ_NEW_QSTR(MP_QSTR__pt), MP_MAP_LOOKUP);
    if (level == NULL || pv == NULL || pn == NULL || pr == NULL || pt == NULL || !mp_obj_is_small_int(pn->value)) {
        return MP_OBJ_NULL;
    }
    bool same = mp_obj_equal(level->value, pv->value);
    if (same && MP_OBJ_SMALL_INT_VALUE(pn->value) <= 1) {
        return MP_OBJ_NULL;  // (the read that looks: _polled)
    }
    spin->value = MP_OBJ_NEW_SMALL_INT(n_spin);
    now->value = MP_OBJ_NEW_SMALL_INT(t);
    if (same) {
        pn->value = MP_OBJ_NEW_SMALL_INT(MP_OBJ_SMALL_INT_VALUE(pn->value) - 1);
    } else {
        pv->value = level->value;
        pn->value = MP_OBJ_NEW_SMALL_INT(pin_poll_reads - 1);
        pr->value = MP_OBJ_NEW_SMALL_INT(0);
        pt->value = now->value;
    }
    return level->value;
}

// (A type of its own, not a built-in function: those act as staticmethods in a class of
// Python's, py/runtime.c mp_convert_member_lookup; this one binds self, as a def does.)
static mp_obj_t pin_value_call(mp_obj_t fun, size_t n_args, size_t n_kw, const mp_obj_t *args) {
    (void)fun;
    if (n_kw == 0 && n_args >= 1 && (n_args == 1 || args[1] == mp_const_none)) {
        mp_obj_t self = args[0];
        if (mp_obj_equal(inst_get(self, MP_QSTR__mode), pin_out_mode)) {
            return inst_get(self, MP_QSTR__out);
        }
        if (mp_obj_is_true(inst_get(self, MP_QSTR__cfg))
            && mp_obj_is_true(mp_obj_dict_get(pin_shim_globals, MP_OBJ_NEW_QSTR(MP_QSTR__dispatching)))) {
            // a handler's read: its first SPIN_LIMIT move no time (_hil._cb_reads counts
            // them); a soft callback's past them is Python's (_hil._callback_read: it spins)
            mp_map_elem_t *reads = shim_slot(MP_QSTR__cb_reads);
            if (reads == NULL || !mp_obj_is_small_int(reads->value)
                || MP_OBJ_SMALL_INT_VALUE(reads->value) < pin_spin_limit) {
                if (reads != NULL && mp_obj_is_small_int(reads->value)) {
                    reads->value = MP_OBJ_NEW_SMALL_INT(MP_OBJ_SMALL_INT_VALUE(reads->value) + 1);
                }
                return inst_get(self, MP_QSTR__level);
            }
        }
        if (pin_poll_reads && mp_obj_is_true(inst_get(self, MP_QSTR__cfg))) {
            mp_obj_t level = pin_read_main(self);
            if (level != MP_OBJ_NULL) {
                return level;
            }
        }
    }
    // (the call into the shim's Python is this call's own: counted once, as the Python method's was)
    if (mp_hil_cur == &mp_hil_counts) {
        mp_hil_counts.ccalls--;
    }
    return mp_call_function_n_kw(pin_value_py, n_args, n_kw, args);
}
static MP_DEFINE_CONST_OBJ_TYPE(pin_value_type, MP_QSTR_function, MP_TYPE_FLAG_BINDS_SELF, call, pin_value_call);
static const mp_obj_base_t pin_value_obj = {&pin_value_type};

// roomy(obj): an instance's attribute table made about twice as large as what it holds. A
// table of py/map.c grows only when full, and a name it lacks (a method of the class: a
// Pin's value, irq) is compared with every slot until an empty one: in a machine.Pin's full
// table of 17, all 17 on each call of a method from the firmware's handler.
static mp_obj_t roomy(mp_obj_t obj) {
    if (!mp_obj_is_obj(obj) || !mp_obj_is_instance_type(mp_obj_get_type(obj))) {
        return mp_const_none;
    }
    mp_obj_instance_t *o = MP_OBJ_TO_PTR(obj);
    mp_map_t old = o->members;
    if (old.is_fixed || old.is_ordered) {
        return mp_const_none;
    }
    mp_map_init(&o->members, old.used * 2 + 5);
    for (size_t i = 0; i < old.alloc; i++) {
        if (mp_map_slot_is_filled(&old, i)) {
            mp_map_lookup(&o->members, old.table[i].key, MP_MAP_LOOKUP_ADD_IF_NOT_FOUND)->value = old.table[i].value;
        }
    }
    m_del(mp_map_elem_t, old.table, old.alloc);
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_1(roomy_obj, roomy);

// -- MCU time: the counters of py/hilcount.h ------------------------------------------

#define N_EXTRA 8  // ccalls, allocs, alloc_bytes, collects, gc_used_bytes, gc_total_bytes, wide, big_bits
static uint32_t cost_ps[256 + N_EXTRA];
static mp_hil_counts_t charged;  // the counters as far as they are charged
static uint64_t main_ps;  // the main program's compute not yet charged (owed_us)
static uint64_t irq_total_ps;  // all the callbacks' compute so far (irq_us: what preempts the main program)

static mp_obj_t new_uint(uint64_t v) {  // (mp_obj_new_int_from_ull always makes a big int)
    return v <= (uint64_t)MP_SMALL_INT_MAX ? MP_OBJ_NEW_SMALL_INT((mp_int_t)v) : mp_obj_new_int_from_ull(v);
}

static uint64_t extra(const mp_hil_counts_t *c, int i) {
    const uint64_t v[N_EXTRA] = {c->ccalls, c->allocs, c->alloc_bytes, c->collects, c->gc_used_bytes, c->gc_total_bytes, c->wide, c->big_bits};
    return v[i];
}

static mp_obj_t exempt(mp_obj_t prefix) {
    size_t len;
    const char *text = mp_obj_str_get_data(prefix, &len);
    if (len == 0 || len >= MP_HIL_PREFIX_MAX) {
        mp_raise_ValueError(MP_ERROR_TEXT("exempt: a folder of 1 to 511 bytes"));
    }
    for (size_t p = 0; p < MP_HIL_PREFIXES; p++) {
        if (mp_hil_exempt_prefix_len[p] == len && memcmp(mp_hil_exempt_prefix[p], text, len) == 0) {
            return mp_const_none;
        }
        if (mp_hil_exempt_prefix_len[p] == 0) {
            memcpy(mp_hil_exempt_prefix[p], text, len);
            mp_hil_exempt_prefix_len[p] = len;
            return mp_const_none;
        }
    }
    mp_raise_ValueError(MP_ERROR_TEXT("exempt: no room for another folder"));
}
static MP_DEFINE_CONST_FUN_OBJ_1(exempt_obj, exempt);

// arm(fn): fn() runs at the firmware's next bytecode branch, where a board runs a scheduled
// callback (py/vm.c, pending_exception_check: the unix port's VM checks at the same
// branches). It goes through this interpreter's own scheduler (mp_sched_schedule, once
// until it has run); a branch in the harness's own code (an exempt module's, as counted
// above: mp_hil_cur is not the firmware's counters) passes it on to the next branch. What fn
// raises is raised in the main program at its next branch (mp_sched_exception), not printed
// and dropped as the scheduler does with a callback's exception.
static bool armed;
static mp_obj_t at_branch(mp_obj_t fn);
static MP_DEFINE_CONST_FUN_OBJ_1(at_branch_obj, at_branch);

static mp_obj_t at_branch(mp_obj_t fn) {
    if (mp_hil_cur != &mp_hil_counts) {
        mp_sched_schedule(MP_OBJ_FROM_PTR(&at_branch_obj), fn);
        return mp_const_none;
    }
    armed = false;
    nlr_buf_t nlr;
    if (nlr_push(&nlr) == 0) {
        mp_call_function_0(fn);
        nlr_pop();
    } else {
        mp_sched_exception(MP_OBJ_FROM_PTR(nlr.ret_val));
    }
    return mp_const_none;
}

static mp_obj_t arm(mp_obj_t fn) {
    if (!armed) {
        armed = mp_sched_schedule(MP_OBJ_FROM_PTR(&at_branch_obj), fn);
    }
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_1(arm_obj, arm);

// The cost table, and the board's heap (this build's bytes) the firmware's collections are
// scheduled by and charged in (py/gc.c, mp_hil_heap_start: only the firmware's own blocks).
static mp_obj_t cost(mp_obj_t weights, mp_obj_t heap) {
    mp_buffer_info_t buf;
    mp_get_buffer_raise(weights, &buf, MP_BUFFER_READ);
    if (buf.len != sizeof(cost_ps)) {
        mp_raise_ValueError(MP_ERROR_TEXT("cost table: wrong length"));
    }
    const uint8_t *b = buf.buf;
    for (size_t i = 0; i < MP_ARRAY_SIZE(cost_ps); i++) {
        cost_ps[i] = get_u32(b + 4 * i);
    }
    mp_hil_heap_start(mp_obj_get_int(heap));
    charged = mp_hil_counts;  // what ran before is not charged
    main_ps = busy_ps = irq_total_ps = 0;
    cost_on = true;
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_2(cost_obj, cost);

// heap_roots(roots): what the harness holds for the firmware as a board holds it in C (its
// devices, timers, queued callbacks: a tuple of at most 8 of the shim's lists, which the
// shim's module holds too), marked from when the board's collector counts the firmware's
// blocks in use (py/gc.c, mp_hil_board_used: no harness module is entered otherwise).
static mp_obj_t heap_roots(mp_obj_t roots) {
    size_t n;
    mp_obj_t *items;
    mp_obj_tuple_get(roots, &n, &items);
    if (n > 8) {
        mp_raise_ValueError(MP_ERROR_TEXT("heap_roots: at most 8"));
    }
    mp_hil_heap_roots(n, items);
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_1(heap_roots_obj, heap_roots);

// The cost of what was counted since the last take, in ps. (Taken at each batch of callbacks,
// twice: the opcodes in blocks of eight, a block that did not change skipped by one memcmp,
// since a handler runs a few dozen kinds of bytecode of the 256.)
static uint64_t counted_ps(bool take) {
    uint64_t ps = 0;
    for (int b = 0; b < 256; b += 8) {
        if (memcmp(&mp_hil_counts.ops[b], &charged.ops[b], 8 * sizeof(uint64_t)) == 0) {
            continue;
        }
        for (int i = b; i < b + 8; i++) {
            ps += (mp_hil_counts.ops[i] - charged.ops[i]) * cost_ps[i];
            if (take) {
                charged.ops[i] = mp_hil_counts.ops[i];
            }
        }
    }
    for (int i = 0; i < N_EXTRA; i++) {
        ps += (extra(&mp_hil_counts, i) - extra(&charged, i)) * cost_ps[256 + i];
    }
    if (take) {
        memcpy(&charged.ccalls, &mp_hil_counts.ccalls, sizeof(mp_hil_counts_t) - offsetof(mp_hil_counts_t, ccalls));
    }
    return ps;
}

static uint64_t take_ps(void) {
    return counted_ps(true);
}

// The main program's compute since the last call, in whole µs (the rest carried).
static mp_obj_t owed_us(void) {
    if (cost_on) {
        main_ps += take_ps();
    }
    uint64_t us = main_ps / 1000000;
    main_ps -= us * 1000000;
    return new_uint(us);
}
static MP_DEFINE_CONST_FUN_OBJ_0(owed_us_obj, owed_us);

// What owed_us() would say now, taking nothing (the compute stays the main program's to charge).
static mp_obj_t owing_us(void) {
    return new_uint(((cost_on ? counted_ps(false) : 0) + main_ps) / 1000000);
}
static MP_DEFINE_CONST_FUN_OBJ_0(owing_us_obj, owing_us);

// branches(fn, every): fn() runs at every every-th branch of the firmware's own code
// (py/hilcount.h, mp_hil_branch_hook; branches(None, 0): no more), with the harness's
// counters (its work is not the firmware's); what it raises is raised there, in the
// firmware, as a pending exception is. Not while it runs (a callback it runs branches too).
// When fn returns an int n > 0, the next call is n branches later instead.
// fn is held by the shim (_Link.branches) as well: this static is no root of the collector.
static mp_obj_t branch_fn = MP_OBJ_NULL;
static bool in_branch_hook;

static void branch_hook(void) {
    mp_hil_branch_left = mp_hil_branch_every;
    if (in_branch_hook) {
        return;
    }
    mp_hil_counts_t *was = mp_hil_cur;
    mp_hil_cur = &mp_hil_sink;
    in_branch_hook = true;
    nlr_buf_t nlr;
    if (nlr_push(&nlr) == 0) {
        mp_obj_t next = mp_call_function_0(branch_fn);
        nlr_pop();
        if (mp_obj_is_small_int(next) && MP_OBJ_SMALL_INT_VALUE(next) > 0) {
            mp_hil_branch_left = (size_t)MP_OBJ_SMALL_INT_VALUE(next);
        }
        in_branch_hook = false;
        mp_hil_cur = was;
    } else {
        in_branch_hook = false;
        mp_hil_cur = was;
        nlr_jump(nlr.ret_val);
    }
}

static mp_obj_t branches(mp_obj_t fn, mp_obj_t every_in) {
    mp_int_t every = mp_obj_get_int(every_in);
    if (fn == mp_const_none || every <= 0) {
        mp_hil_branch_hook = NULL;
        branch_fn = MP_OBJ_NULL;
        return mp_const_none;
    }
    branch_fn = fn;
    mp_hil_branch_every = mp_hil_branch_left = (size_t)every;
    mp_hil_branch_hook = branch_hook;
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_2(branches_obj, branches);

// Callbacks run (IRQ handlers, Timer callbacks): what the main program computed before
// them is its own; theirs keeps the CPU busy from their instant (or from when the ones
// before are done) for as long as it costs: the main program goes on after that
// (busy_us, which the shim waits out after a wait); irq_us(): all the callbacks' compute so
// far, whole µs (the shim lengthens the main program's compute by what fired during it).
static void irq_begin(void) {
    if (cost_on) {
        main_ps += take_ps();
    }
}

static void irq_end(mp_obj_t now_us) {
    if (cost_on) {
        uint64_t ps = take_ps();
        uint64_t start = (uint64_t)mp_obj_get_int(now_us) * 1000000;
        busy_ps = (busy_ps > start ? busy_ps : start) + ps;
        irq_total_ps += ps;
    }
}

static mp_obj_t irq_begin_py(void) {
    irq_begin();
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_0(irq_begin_obj, irq_begin_py);

static mp_obj_t irq_end_py(mp_obj_t now_us) {
    irq_end(now_us);
    return mp_const_none;
}
static MP_DEFINE_CONST_FUN_OBJ_1(irq_end_obj, irq_end_py);

static mp_obj_t busy_us(void) {  // (rounded up: the main program goes on once they are done)
    return new_uint((busy_ps + 999999) / 1000000);
}
static MP_DEFINE_CONST_FUN_OBJ_0(busy_us_obj, busy_us);

static mp_obj_t irq_us(void) {  // (whole µs, rounded down: a difference of two is what ran between)
    return new_uint(irq_total_ps / 1000000);
}
static MP_DEFINE_CONST_FUN_OBJ_0(irq_us_obj, irq_us);
static mp_obj_t counts(void) {
    static mp_hil_counts_t now;
    now = mp_hil_counts;  // (before this function's own allocations)
    mp_obj_t ops = mp_obj_new_list(256, NULL);
    for (int i = 0; i < 256; i++) {
        mp_obj_list_store(ops, MP_OBJ_NEW_SMALL_INT(i), new_uint(now.ops[i]));
    }
    mp_obj_t d = mp_obj_new_dict(N_EXTRA + 1);
    static const qstr names[N_EXTRA] = {MP_QSTR_ccalls, MP_QSTR_allocs, MP_QSTR_alloc_bytes, MP_QSTR_collects, MP_QSTR_gc_used_bytes, MP_QSTR_gc_total_bytes, MP_QSTR_wide, MP_QSTR_big_bits};
    mp_obj_dict_store(d, MP_OBJ_NEW_QSTR(MP_QSTR_ops), ops);
    for (int i = 0; i < N_EXTRA; i++) {
        mp_obj_dict_store(d, MP_OBJ_NEW_QSTR(names[i]), new_uint(extra(&now, i)));
    }
    return d;
}
static MP_DEFINE_CONST_FUN_OBJ_0(counts_obj, counts);

// One running function as (file, function, line): its prelude decoded as py/vm.c's exception
// handler does for a traceback (MP_BC_PRELUDE_SIG_DECODE, mp_bytecode_get_source_line).
static mp_obj_t frame(const mp_code_state_t *cs) {
    const byte *ip = cs->fun_bc->bytecode;
    MP_BC_PRELUDE_SIG_DECODE(ip);
    MP_BC_PRELUDE_SIZE_DECODE(ip);
    const byte *line_info_top = ip + n_info;
    const byte *bytecode_start = ip + n_info + n_cell;
    qstr block_name = mp_decode_uint_value(ip);
    for (size_t i = 0; i < 1 + n_pos_args + n_kwonly_args; ++i) {
        ip = mp_decode_uint_skip(ip);
    }
    #if MICROPY_EMIT_BYTECODE_USES_QSTR_TABLE
    block_name = cs->fun_bc->context->constants.qstr_table[block_name];
    qstr source_file = cs->fun_bc->context->constants.qstr_table[0];
    #else
    qstr source_file = cs->fun_bc->context->constants.source_file;
    #endif
    size_t offset = cs->ip > bytecode_start ? (size_t)(cs->ip - bytecode_start) : 0;
    size_t line = mp_bytecode_get_source_line(ip, line_info_top, offset);
    mp_obj_t item[3] = {MP_OBJ_NEW_QSTR(source_file), MP_OBJ_NEW_QSTR(block_name), MP_OBJ_NEW_SMALL_INT(line)};
    return mp_obj_new_tuple(3, item);
}

static mp_obj_t stack(size_t n_args, const mp_obj_t *args) {
    bool all = n_args > 0 && mp_obj_is_true(args[0]);
    size_t depth = mp_hil_depth < MP_HIL_STACK_MAX ? mp_hil_depth : MP_HIL_STACK_MAX;
    mp_obj_t out = mp_obj_new_list(0, NULL);
    for (size_t i = 0; i < depth; i++) {
        if (all || mp_hil_stack_counted[i]) {
            mp_obj_list_append(out, frame(mp_hil_stack[i]));
        }
    }
    return out;
}
static MP_DEFINE_CONST_FUN_OBJ_VAR_BETWEEN(stack_obj, 0, 1, stack);

static const mp_rom_map_elem_t hilfast_globals_table[] = {
    {MP_ROM_QSTR(MP_QSTR___name__), MP_ROM_QSTR(MP_QSTR__hilfast)},
    {MP_ROM_QSTR(MP_QSTR_apply_state), MP_ROM_PTR(&apply_state_obj)},
    {MP_ROM_QSTR(MP_QSTR_EDGES_MAX), MP_ROM_INT(EDGES_MAX)},
    {MP_ROM_QSTR(MP_QSTR_merge_edges), MP_ROM_PTR(&merge_edges_obj)},
    {MP_ROM_QSTR(MP_QSTR_link), MP_ROM_PTR(&link_new_obj)},
    {MP_ROM_QSTR(MP_QSTR_defers), MP_ROM_TRUE},  // apply_state's dispatch keeps soft callbacks queued from _Link.defer_from on
    {MP_ROM_QSTR(MP_QSTR_roomy), MP_ROM_PTR(&roomy_obj)},
    {MP_ROM_QSTR(MP_QSTR_pin_setup), MP_ROM_PTR(&pin_setup_obj)},
    {MP_ROM_QSTR(MP_QSTR_pin_value), MP_ROM_PTR(&pin_value_obj)},
    {MP_ROM_QSTR(MP_QSTR_exempt), MP_ROM_PTR(&exempt_obj)},
    {MP_ROM_QSTR(MP_QSTR_arm), MP_ROM_PTR(&arm_obj)},
    {MP_ROM_QSTR(MP_QSTR_cost), MP_ROM_PTR(&cost_obj)},
    {MP_ROM_QSTR(MP_QSTR_heap_roots), MP_ROM_PTR(&heap_roots_obj)},
    {MP_ROM_QSTR(MP_QSTR_owed_us), MP_ROM_PTR(&owed_us_obj)},
    {MP_ROM_QSTR(MP_QSTR_owing_us), MP_ROM_PTR(&owing_us_obj)},
    {MP_ROM_QSTR(MP_QSTR_branches), MP_ROM_PTR(&branches_obj)},
    {MP_ROM_QSTR(MP_QSTR_counts), MP_ROM_PTR(&counts_obj)},
    {MP_ROM_QSTR(MP_QSTR_irq_begin), MP_ROM_PTR(&irq_begin_obj)},
    {MP_ROM_QSTR(MP_QSTR_irq_end), MP_ROM_PTR(&irq_end_obj)},
    {MP_ROM_QSTR(MP_QSTR_busy_us), MP_ROM_PTR(&busy_us_obj)},
    {MP_ROM_QSTR(MP_QSTR_irq_us), MP_ROM_PTR(&irq_us_obj)},
    {MP_ROM_QSTR(MP_QSTR_stack), MP_ROM_PTR(&stack_obj)},
};
static MP_DEFINE_CONST_DICT(hilfast_globals, hilfast_globals_table);

const mp_obj_module_t hilfast_user_cmodule = {
    .base = {&mp_type_module},
    .globals = (mp_obj_dict_t *)&hilfast_globals,
};

MP_REGISTER_MODULE(MP_QSTR__hilfast, hilfast_user_cmodule);
