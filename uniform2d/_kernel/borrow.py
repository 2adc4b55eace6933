"""Borrowed copies of the kernel's structrefs, for loops that read their arrays
millions of times.

numba counts references to every array: each read of a structref's array field
(``m.tv``) increments the array's count and a decrement follows -- two *locked*
instructions, which also stall the pipeline until pending memory accesses are
done.  In INSERT's loop, which reads a few hundred fields per step, they took
about 60% of the time.  An array whose meminfo is null (what ``numba.carray``
makes of a raw pointer) is counted by a null test instead.

:func:`borrowed` gives a new structref of the same type whose array fields are
such views of the original's arrays (other fields copied); the original keeps
owning the memory, so the views are valid while it lives and is not changed
behind their back.  An array the loop replaces (a buffer that grows) is a normal
owned array.  :func:`settle` copies the borrowed copy's state back: scalars,
and every array field that no longer views the original's (so a grown buffer
ends up owned by the original).  Structref fields are neither copied into
views nor back: a nested structref is borrowed and settled on its own.
"""

from numba.core import cgutils, types
from numba.experimental.jitclass.base import imp_dtor
from numba.experimental.structref import _Utils
from numba.extending import intrinsic

__all__ = ["borrowed", "settle"]


def _fields(typ):
    return typ.field_dict.items()


@intrinsic
def borrowed(typingctx, src_t):
    """A copy of structref ``src`` whose arrays are views without a meminfo."""
    if not isinstance(src_t, types.StructRef):
        return None

    def codegen(context, builder, sig, args):
        model = context.data_model_manager[src_t.get_data_type()]
        alloc_type = model.get_value_type()
        meminfo = context.nrt.meminfo_alloc_dtor(
            builder,
            context.get_constant(types.uintp, context.get_abi_sizeof(alloc_type)),
            imp_dtor(context, builder.module, src_t),
        )
        data = builder.bitcast(context.nrt.meminfo_data(builder, meminfo), alloc_type.as_pointer())
        builder.store(cgutils.get_null_value(alloc_type), data)
        out = context.make_helper(builder, src_t)
        out.meminfo = meminfo
        utils = _Utils(context, builder, src_t)
        dst = utils.get_data_struct(out._getvalue())
        src = utils.get_data_struct(args[0])
        for name, ftype in _fields(src_t):
            val = getattr(src, name)
            if isinstance(ftype, types.Array):
                view = context.make_array(ftype)(context, builder, value=val)
                view.meminfo = cgutils.get_null_value(view.meminfo.type)
                view.parent = cgutils.get_null_value(view.parent.type)
                val = view._getvalue()
            else:
                context.nrt.incref(builder, ftype, val)
            setattr(dst, name, val)
        return out._getvalue()

    return src_t(src_t), codegen


@intrinsic
def settle(typingctx, dst_t, src_t):
    """Copy the state of ``src`` (a :func:`borrowed` copy of ``dst``) back into
    ``dst``: scalar fields, and the array fields whose data moved."""
    if dst_t != src_t or not isinstance(dst_t, types.StructRef):
        return None

    def codegen(context, builder, sig, args):
        utils = _Utils(context, builder, dst_t)
        dst = utils.get_data_struct(args[0])
        src = utils.get_data_struct(args[1])
        for name, ftype in _fields(dst_t):
            if isinstance(ftype, types.StructRef):
                continue
            new = getattr(src, name)
            old = getattr(dst, name)
            if isinstance(ftype, types.Array):
                a = context.make_array(ftype)(context, builder, value=new)
                b = context.make_array(ftype)(context, builder, value=old)
                moved = builder.icmp_unsigned("!=", a.data, b.data)
                with builder.if_then(moved):
                    context.nrt.incref(builder, ftype, new)
                    context.nrt.decref(builder, ftype, old)
                    setattr(dst, name, new)
            elif isinstance(ftype, (types.Integer, types.Float, types.Boolean)):
                setattr(dst, name, new)
            else:  # nothing else is expected in the kernel's structrefs
                raise TypeError(f"settle: field {name} of type {ftype}")
        return context.get_dummy_value()

    return types.none(dst_t, src_t), codegen

