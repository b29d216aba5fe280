// A C++ settings struct bound as a Python class whose fields are declared once: each field's
// name, member and doc become a documented read-write property, and the list of them makes
// the keyword constructor (RenderOptions(spp=16, max_depth=4)), the pickling (a distributed
// render sends its options to the Dask workers), equality and the repr.
#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace patina_py {

namespace nb = nanobind;

template <class T>
class Record {
public:
    Record(nb::handle scope, const char* name, const char* doc)
        : m_class(scope, name, doc), m_fields(std::make_shared<std::vector<Field>>()), m_name(name) {}

    // A field as it is in C++ (a number, a bool, a bound struct).
    template <class M>
    Record& field(const char* name, M T::*member, const char* doc) {
        m_class.def_rw(name, member, doc);
        m_fields->push_back({name, [member](const T& t) { return nb::cast(t.*member); },
                             [member](T& t, nb::handle v) { t.*member = nb::cast<M>(v); }});
        return *this;
    }

    // Three floats (a point or direction): any 3 numbers in Python, read as a tuple.
    Record& vector3(const char* name, float (T::*member)[3], const char* doc) {
        auto get = [member](const T& t) { return nb::make_tuple((t.*member)[0], (t.*member)[1], (t.*member)[2]); };
        auto set = [member, name, type = m_name](T& t, nb::handle value) {
            std::vector<float> v;
            if (!nb::try_cast(value, v) || v.size() != 3)
                throw std::invalid_argument(type + "." + name + ": must be 3 numbers");
            std::copy(v.begin(), v.end(), t.*member);
        };
        m_class.def_prop_rw(name, get, [set](T& t, nb::handle v) { set(t, v); }, doc);
        m_fields->push_back({name, [get](const T& t) { return nb::object(get(t)); }, set});
        return *this;
    }

    // A field Python sees as a name (an enum): `get` gives it, `set` takes it (and throws
    // std::invalid_argument naming the field and the names it knows).
    Record& named(const char* name, std::string (*get)(const T&), void (*set)(T&, const std::string&), const char* doc) {
        m_class.def_prop_rw(name, get, set, doc);
        m_fields->push_back({name, [get](const T& t) { return nb::cast(get(t)); },
                             [set](T& t, nb::handle v) { set(t, nb::cast<std::string>(v)); }});
        return *this;
    }

    // The constructor, pickling, equality and repr, from the fields declared so far.
    nb::class_<T>& finish() {
        auto fields = m_fields;
        const std::string type = m_name;
        m_class.def(
            "__init__",
            [fields, type](T* t, const nb::kwargs& values) {
                new (t) T{};
                set_all(*fields, *t, values, type);
            },
            "Every field at its default but those given by name.");
        m_class.def("__getstate__", [fields](const T& t) { return state(*fields, t); });
        m_class.def("__setstate__", [fields, type](T& t, const nb::dict& values) {
            new (&t) T{};
            set_all(*fields, t, values, type);
        });
        m_class.def("__eq__", [fields](const T& a, const T& b) { return state(*fields, a).equal(state(*fields, b)); });
        m_class.def("__repr__", [fields, type](const T& t) {
            std::string out = type + "(";
            for (const Field& f : *fields)
                out += (&f == &fields->front() ? "" : ", ") + std::string(f.name) + "=" +
                       nb::cast<std::string>(nb::repr(f.get(t)));
            return out + ")";
        });
        return m_class;
    }

private:
    struct Field {
        const char* name;
        std::function<nb::object(const T&)> get;
        std::function<void(T&, nb::handle)> set;
    };

    static nb::dict state(const std::vector<Field>& fields, const T& t) {
        nb::dict d;
        for (const Field& f : fields) d[f.name] = f.get(t);
        return d;
    }

    // Each value to its field by name; an unknown name, or a value of the wrong type, is a
    // TypeError naming the field (a value out of range is the settings' own check's).
    static void set_all(const std::vector<Field>& fields, T& t, const nb::dict& values, const std::string& type) {
        for (auto [key, value] : values) {
            const std::string name = nb::cast<std::string>(key);
            const Field* field = nullptr;
            std::string known;
            for (const Field& f : fields) {
                if (name == f.name) field = &f;
                known += (known.empty() ? "" : ", ") + std::string(f.name);
            }
            if (!field) throw nb::type_error((type + ": no field '" + name + "' (it has " + known + ")").c_str());
            try {
                field->set(t, value);
            } catch (const nb::cast_error&) {
                const std::string given = nb::cast<std::string>(nb::repr(value));
                throw nb::type_error((type + "." + name + ": cannot take " + given).c_str());
            }
        }
    }

    nb::class_<T> m_class;
    std::shared_ptr<std::vector<Field>> m_fields;
    std::string m_name;
};

}  // namespace patina_py
