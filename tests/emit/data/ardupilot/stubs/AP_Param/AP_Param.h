// Test stub: the parts of ArduPilot's AP_Param a generated parameter table uses.
#pragma once

#include <cstdint>
#include <cstddef>

#define CLASS_NO_COPY(c) c(const c &other) = delete; c &operator=(const c&) = delete

enum ap_var_type { AP_PARAM_NONE, AP_PARAM_INT8, AP_PARAM_INT16, AP_PARAM_INT32, AP_PARAM_FLOAT };

template<typename T, ap_var_type PT>
class AP_ParamT
{
public:
    static constexpr ap_var_type vtype = PT;
    T get() const { return _value; }
private:
    T _value;
};

typedef AP_ParamT<int8_t, AP_PARAM_INT8> AP_Int8;
typedef AP_ParamT<int16_t, AP_PARAM_INT16> AP_Int16;
typedef AP_ParamT<int32_t, AP_PARAM_INT32> AP_Int32;
typedef AP_ParamT<float, AP_PARAM_FLOAT> AP_Float;

class AP_Param
{
public:
    struct GroupInfo {
        const char *name;
        ptrdiff_t offset;
        union {
            const struct GroupInfo *group_info;
            const float def_value;
        };
        uint16_t flags;
        uint8_t idx;
        uint8_t type;
    };
    static void setup_object_defaults(const void *object_pointer, const struct GroupInfo *group_info)
    {
        (void)object_pointer;
        (void)group_info;
    }
};

// As in ArduPilot's AP_Param.h: an enable switch hides its group's other parameters while 0.
#define AP_PARAM_FLAG_ENABLE (1<<2)

// As in ArduPilot: the index must fit the 6-bit group element field.
#define AP_GROUPINFO_FLAGS(name, idx, clazz, element, def, flags) \
    { name, (ptrdiff_t)offsetof(clazz, element), {def_value : def}, flags, idx, \
      (uint8_t)decltype(clazz::element)::vtype }
#define AP_GROUPINFO(name, idx, clazz, element, def) AP_GROUPINFO_FLAGS(name, idx, clazz, element, def, 0)
#define AP_GROUPEND { "", 0, { group_info : nullptr }, 0, 0xFF, AP_PARAM_NONE }
